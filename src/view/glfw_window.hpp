#pragma once
// The viewer's window: a GLFW window whose OpenGL 4.5 core context is a pr::Context like the
// headless ones (platform/context_glfw.cpp). GLFW opens libGL itself (dlopen) and glad is loaded
// through glfwGetProcAddress, so nothing links libGL. Only context_glfw.cpp includes GLFW's
// header; callers see the handle as an opaque pointer (Dear ImGui's GLFW backend takes it).
#include "platform/context.hpp"

#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace pr {

class GlfwWindow final : public Context {
public:
    struct Size {
        int width = 0;
        int height = 0;
    };

    // Opens a window of `width` x `height` screen coordinates with a current 4.5 core context.
    // Throws pr::Error("view", "cannot open a window: …") when there is no display or no 4.5
    // core context (GLFW's own message follows).
    static std::unique_ptr<GlfwWindow> open(int width, int height, const std::string& title);
    ~GlfwWindow() override;

    GLFWwindow* handle() const { return window_; }
    Size framebuffer_size() const; // pixels (differs from window_size() on high-DPI screens)
    Size window_size() const;      // screen coordinates
    float content_scale() const;   // the monitor's UI scale (1 on ordinary screens)

    bool should_close() const;
    void request_close();
    void set_title(const std::string& title);
    void set_swap_interval(int interval); // 1: vsync, 0: as fast as possible
    void swap_buffers();
    // Processes events; waits up to `timeout_s` for one when > 0.
    void poll_events(double timeout_s = 0.0);
    // Paths dropped onto the window since the last call (in drop order).
    std::vector<std::string> take_dropped_files();
    // Keys pressed since the last call, in order (GLFW key codes: ASCII for letters, digits and
    // brackets; repeats left out), each with whether Shift was held. Every press counts, however
    // short: polled once a frame, a press and release within one slow frame were lost.
    struct KeyPress {
        int key = 0;
        bool shift = false;
    };
    std::vector<KeyPress> take_key_presses();
    // Keys pressed and released again since the last call (GLFW key codes): a frame that reads
    // the keys' state sees them up, as if never pressed.
    std::vector<int> take_taps();

private:
    GlfwWindow() = default;
    GLFWwindow* window_ = nullptr;
    std::vector<std::string> dropped_;
    std::vector<KeyPress> keys_;
    std::vector<int> pressed_unseen_; // pressed since the last take_taps()
    std::vector<int> taps_;
    friend void glfw_drop_callback(GLFWwindow*, int, const char**);
    friend void glfw_key_callback(GLFWwindow*, int, int, int, int);
};

} // namespace pr
