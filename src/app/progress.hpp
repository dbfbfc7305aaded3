#pragma once
// "LABEL: [#####.....]  50%" on stderr, redrawn in place, only when stderr is a terminal; cleared
// when done (or destroyed), so piped output and logs never see it.
#include <algorithm>
#include <cstdio>
#include <string>
#include <unistd.h>

namespace pr {

class ProgressBar {
public:
    explicit ProgressBar(std::string label) : label_(std::move(label)), enabled_(isatty(fileno(stderr)) != 0) {}
    ~ProgressBar() { clear(); }
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    void operator()(double fraction)
    {
        if (!enabled_) return;
        const int width = 30, filled = std::clamp(int(fraction * width + 0.5), 0, width);
        std::fprintf(stderr, "\r%s: [%s%s] %3d%%", label_.c_str(), std::string(std::size_t(filled), '#').c_str(),
                     std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100.0 + 0.5));
        std::fflush(stderr);
        shown_ = true;
    }
    void clear()
    {
        if (shown_) std::fprintf(stderr, "\r%*s\r", int(label_.size()) + 40, "");
        shown_ = false;
    }

private:
    std::string label_;
    bool enabled_;
    bool shown_ = false;
};

} // namespace pr
