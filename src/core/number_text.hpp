#pragma once
// Numbers printed for people, where a rounded value would say something false.
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>

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

// A float as the double of the shortest decimal that reads back as it (178.9, not the float's
// exact 178.89999389648438), for reports a person reads and a script feeds back.
inline double shortest_decimal(float f)
{
    char text[32];
    const auto [end, error] = std::to_chars(text, text + sizeof text - 1, f);
    if (error != std::errc()) return double(f);
    *end = '\0';
    return std::strtod(text, nullptr);
}

} // namespace pr
