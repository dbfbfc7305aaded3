#pragma once
// "LABEL: [#####.....]  50%" on stderr, redrawn in place (core/error.hpp, status_line: warnings
// go above it), only when stderr is a terminal, fitted to its width; cleared when done (or
// destroyed), so piped output and logs never see it. Off a terminal, a task still
// running after `notice_after_s` (10 s) says once, on a line of its own, how far it is and about
// how long it has left: a cone map of 4096² takes minutes, and a log showed nothing at all
// (found by an exploratory session).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <sys/ioctl.h>
#include <unistd.h>

#include "core/error.hpp"

namespace pr {

class ProgressBar {
public:
    explicit ProgressBar(std::string label) : ProgressBar(std::move(label), stderr, isatty(fileno(stderr)) != 0) {}
    // Drawn on `out` if `enabled`, else the notice after `notice_after_s` (tests). `columns`: the
    // terminal's width, 0 to ask the terminal `out` is at each draw (80 if it does not say).
    ProgressBar(std::string label, std::FILE* out, bool enabled, double notice_after_s = 10.0, int columns = 0)
        : label_(one_line(label)), out_(out), enabled_(enabled), notice_after_s_(notice_after_s), columns_(columns)
    {
    }
    ~ProgressBar() { clear(); }
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    void operator()(double fraction)
    {
        if (!enabled_) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
            if (noticed_ || !(fraction < 1.0) || elapsed < notice_after_s_) return;
            // Under 1 %, how far without an estimate (from less it says little, and from nothing,
            // infinity), and the estimate once 1 % is done: the note waited for 1 %, which an
            // 8192² relaxed map reached after 77 s (found by an exploratory session, forty-fourth).
            if (!(fraction >= 0.01)) {
                if (!early_) {
                    early_ = true;
                    std::fprintf(out_, "prismrelief: note: %s: %.1f%% done after %.0f s (an estimate once 1%% is done)\n",
                                 label_.c_str(), std::max(fraction, 0.0) * 100.0, elapsed);
                    std::fflush(out_);
                }
                return;
            }
            noticed_ = true;
            std::fprintf(out_, "prismrelief: note: %s: %d%% done after %.0f s, about %.0f s more\n", label_.c_str(),
                         int(fraction * 100.0), elapsed, std::ceil(elapsed * (1.0 - fraction) / fraction));
            std::fflush(out_);
            return;
        }
        status_line(out_, bar_line(label_, fraction, columns_ > 0 ? columns_ : terminal_columns(out_)));
        shown_ = true;
    }
    void clear()
    {
        if (shown_) status_line(out_, "");
        shown_ = false;
    }

    // "LABEL: [#####.....]  50%" in at most `columns` - 1 columns (a line as wide as the terminal
    // wraps on some terminals, and "\r" then goes back to its last row only: a bar for a long map
    // name left a new line at every redraw, found by an exploratory session). The bar is 30 wide
    // where it fits, down to 10; then the label loses its middle ("...").
    static std::string bar_line(const std::string& label, double fraction, int columns)
    {
        char percent[8];
        std::snprintf(percent, sizeof percent, "%3d%%", std::clamp(int(fraction * 100.0 + 0.5), 0, 100));
        // Under 20 columns, the percentage alone where it fits (the bar took 19 columns whatever
        // the width and wrapped, and a signal's clearing went back to its last row only; found by
        // an exploratory session, thirty-third).
        if (columns < 20) return columns - 1 >= 4 ? std::string(percent) : std::string();
        const int room = columns - 1, fixed = 9; // ": [", "] ", "100%"
        const int length = int(display_columns(label));
        int width = std::clamp(room - fixed - length, 10, 30);
        // (Narrower still on a very narrow terminal, where the label keeps 12 columns, or all of
        // a shorter one: "bench" took 12 too, and its bar came out narrower than 10 where 15 fit;
        // found by a review.)
        const int label_room = std::min(12, length);
        if (room - fixed - width < label_room) width = std::max(room - fixed - label_room, 3);
        const int filled = std::clamp(int(fraction * width + 0.5), 0, width);
        const std::string shown = shortened_to_columns(label, std::size_t(room - fixed - width));
        return shown + ": [" + std::string(std::size_t(filled), '#') + std::string(std::size_t(width - filled), '.') +
               "] " + percent;
    }

private:
    static int terminal_columns(std::FILE* out)
    {
        winsize size{};
        return ioctl(fileno(out), TIOCGWINSZ, &size) == 0 && size.ws_col > 0 ? int(size.ws_col) : 80;
    }

    std::string label_;
    std::FILE* out_;
    bool enabled_;
    double notice_after_s_;
    int columns_;
    bool noticed_ = false;
    bool early_ = false; // said after notice_after_s_, under 1 % done
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    bool shown_ = false;
};

// Progress of several tasks one after the other, by name (the renderer's cone-map builds:
// Renderer::ConeProgress): a bar per task, labelled "building <what>", cleared when it reaches 1.
// A task that is done at its first report (a map read from the cache) shows nothing.
class TaskProgress {
public:
    TaskProgress() : TaskProgress(stderr, isatty(fileno(stderr)) != 0) {}
    TaskProgress(std::FILE* out, bool enabled, double notice_after_s = 10.0, int columns = 0)
        : out_(out), enabled_(enabled), notice_after_s_(notice_after_s), columns_(columns)
    {
    }

    void operator()(const std::string& what, double fraction)
    {
        if (!bar_ || what != what_) {
            bar_.reset();
            if (fraction >= 1.0) return;
            bar_.emplace("building " + what, out_, enabled_, notice_after_s_, columns_);
            what_ = what;
        }
        (*bar_)(fraction);
        if (fraction >= 1.0) bar_.reset();
    }

private:
    std::FILE* out_;
    bool enabled_;
    double notice_after_s_;
    int columns_;
    std::optional<ProgressBar> bar_;
    std::string what_;
};

} // namespace pr
