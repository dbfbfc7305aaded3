#pragma once
// Numbers printed for people, where a rounded value would say something false.
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pr {

// `value` with `digits` decimals, or more (up to 9) where those would round a value strictly
// between `low` and `high` to one of them: "1.0000" is an IoU of exactly 1, "0.0%" or "100.0%"
// a coverage of no pixel or of every one.
inline std::string bounded_text(double value, int digits, double low, double high)
{
    char text[64];
    for (;; ++digits) {
        std::snprintf(text, sizeof text, "%.*f", digits, value);
        if (!(value > low && value < high) || digits >= 9) return text;
        const double shown = std::strtod(text, nullptr);
        if (shown != low && shown != high) return text;
    }
}

} // namespace pr
