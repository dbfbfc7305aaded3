// GLFW backend: the viewer's window and its OpenGL 4.5 core context (see view/glfw_window.hpp).
// GLFW opens libGL at run time for GLX (and libEGL for Wayland), so the binary links no `gl*`
// provider; glad is loaded through glfwGetProcAddress like the other backends' GetProcAddress.
#include "view/glfw_window.hpp"

#include "core/error.hpp"
#include "platform/mesa_cache.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <string>

namespace pr {
namespace {

std::string& last_glfw_error()
{
    static std::string e;
    return e;
}

void glfw_error_callback(int, const char* description)
{
    last_glfw_error() = description ? description : "unknown GLFW error";
}

void* glfw_get_proc(const char* name)
{
    return reinterpret_cast<void*>(glfwGetProcAddress(name));
}

[[noreturn]] void fail(const std::string& what)
{
    const std::string why = last_glfw_error().empty() ? "" : " (" + last_glfw_error() + ")";
    throw Error("view", "cannot open a window: " + what + why);
}

} // namespace

void glfw_drop_callback(GLFWwindow* window, int count, const char** paths)
{
    auto* self = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(window));
    if (!self) return;
    for (int i = 0; i < count; ++i)
        if (paths[i]) self->dropped_.emplace_back(paths[i]);
}

// Queued for the viewer (take_key_presses). Set before Dear ImGui's backend installs its own,
// which calls this one first.
void glfw_key_callback(GLFWwindow* window, int key, int /*scancode*/, int action, int mods)
{
    auto* self = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(window));
    if (!self) return;
    if (action == GLFW_RELEASE) {
        auto& unseen = self->pressed_unseen_;
        if (const auto at = std::find(unseen.begin(), unseen.end(), key); at != unseen.end()) {
            unseen.erase(at);
            self->taps_.push_back(key);
        }
        return;
    }
    if (action != GLFW_PRESS) return;
    self->keys_.push_back({key, (mods & GLFW_MOD_SHIFT) != 0});
    self->pressed_unseen_.push_back(key);
}

std::unique_ptr<GlfwWindow> GlfwWindow::open(int width, int height, const std::string& title)
{
    last_glfw_error().clear();
    prepare_mesa_shader_cache(); // (a Mesa libGL reads it when the window's context is made)
    glfwSetErrorCallback(&glfw_error_callback);
    if (!glfwInit()) fail("no display (is DISPLAY set? under CI use xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE); // high-DPI: window size in logical units
    glfwWindowHint(GLFW_DEPTH_BITS, 0);               // the renderer draws into its own FBO
    std::unique_ptr<GlfwWindow> w(new GlfwWindow());
    w->window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!w->window_) {
        glfwTerminate();
        fail("no OpenGL 4.5 core context");
    }
    glfwSetWindowUserPointer(w->window_, w.get());
    glfwSetDropCallback(w->window_, &glfw_drop_callback);
    glfwSetKeyCallback(w->window_, &glfw_key_callback);
    glfwMakeContextCurrent(w->window_);
    w->load_gl(&glfw_get_proc, "view", "GLFW");
    return w;
}

GlfwWindow::~GlfwWindow()
{
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

GlfwWindow::Size GlfwWindow::framebuffer_size() const
{
    Size s;
    glfwGetFramebufferSize(window_, &s.width, &s.height);
    return s;
}

GlfwWindow::Size GlfwWindow::window_size() const
{
    Size s;
    glfwGetWindowSize(window_, &s.width, &s.height);
    return s;
}

float GlfwWindow::content_scale() const
{
    float x = 1.0f, y = 1.0f;
    glfwGetWindowContentScale(window_, &x, &y);
    return x > 0.0f ? x : 1.0f;
}

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_) != 0; }
void GlfwWindow::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void GlfwWindow::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
void GlfwWindow::set_swap_interval(int interval) { glfwSwapInterval(interval); }
void GlfwWindow::swap_buffers() { glfwSwapBuffers(window_); }

void GlfwWindow::poll_events(double timeout_s)
{
    if (timeout_s > 0.0)
        glfwWaitEventsTimeout(timeout_s);
    else
        glfwPollEvents();
}

std::vector<GlfwWindow::KeyPress> GlfwWindow::take_key_presses()
{
    std::vector<KeyPress> out;
    out.swap(keys_);
    return out;
}

std::vector<int> GlfwWindow::take_taps()
{
    pressed_unseen_.clear(); // (still down: the frame that takes these reads them down)
    std::vector<int> out;
    out.swap(taps_);
    return out;
}

std::vector<std::string> GlfwWindow::take_dropped_files()
{
    std::vector<std::string> out;
    out.swap(dropped_);
    return out;
}

} // namespace pr
