#pragma once
// "LABEL: [#####.....]  50%" on stderr, redrawn in place, only when stderr is a terminal; cleared
// when done (or destroyed), so piped output and logs never see it. Off a terminal, a task still
// running after `notice_after_s` (10 s) says once, on a line of its own, how far it is and about
// how long it has left: a cone map of 4096² takes minutes, and a log showed nothing at all
// (found by an exploratory session).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <unistd.h>

namespace pr {

class ProgressBar {
public:
    explicit ProgressBar(std::string label) : ProgressBar(std::move(label), stderr, isatty(fileno(stderr)) != 0) {}
    // Drawn on `out` if `enabled`, else the notice after `notice_after_s` (tests).
    ProgressBar(std::string label, std::FILE* out, bool enabled, double notice_after_s = 10.0)
        : label_(std::move(label)), out_(out), enabled_(enabled), notice_after_s_(notice_after_s)
    {
    }
    ~ProgressBar() { clear(); }
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    void operator()(double fraction)
    {
        if (!enabled_) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
            // (From 1 % on: an estimate from less says little, and from nothing, infinity.)
            if (noticed_ || !(fraction >= 0.01 && fraction < 1.0) || elapsed < notice_after_s_) return;
            noticed_ = true;
            std::fprintf(out_, "prismrelief: note: %s: %d%% done after %.0f s, about %.0f s more\n", label_.c_str(),
                         int(fraction * 100.0), elapsed, std::ceil(elapsed * (1.0 - fraction) / fraction));
            std::fflush(out_);
            return;
        }
        const int width = 30, filled = std::clamp(int(fraction * width + 0.5), 0, width);
        std::fprintf(out_, "\r%s: [%s%s] %3d%%", label_.c_str(), std::string(std::size_t(filled), '#').c_str(),
                     std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100.0 + 0.5));
        std::fflush(out_);
        shown_ = true;
    }
    void clear()
    {
        if (shown_) std::fprintf(out_, "\r%*s\r", int(label_.size()) + 40, "");
        shown_ = false;
    }

private:
    std::string label_;
    std::FILE* out_;
    bool enabled_;
    double notice_after_s_;
    bool noticed_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    bool shown_ = false;
};

// Progress of several tasks one after the other, by name (the renderer's cone-map builds:
// Renderer::ConeProgress): a bar per task, labelled "building <what>", cleared when it reaches 1.
// A task that is done at its first report (a map read from the cache) shows nothing.
class TaskProgress {
public:
    TaskProgress() : TaskProgress(stderr, isatty(fileno(stderr)) != 0) {}
    TaskProgress(std::FILE* out, bool enabled, double notice_after_s = 10.0)
        : out_(out), enabled_(enabled), notice_after_s_(notice_after_s)
    {
    }

    void operator()(const std::string& what, double fraction)
    {
        if (!bar_ || what != what_) {
            bar_.reset();
            if (fraction >= 1.0) return;
            bar_.emplace("building " + what, out_, enabled_, notice_after_s_);
            what_ = what;
        }
        (*bar_)(fraction);
        if (fraction >= 1.0) bar_.reset();
    }

private:
    std::FILE* out_;
    bool enabled_;
    double notice_after_s_;
    std::optional<ProgressBar> bar_;
    std::string what_;
};

} // namespace pr
