#pragma once
// Built-in procedural maps ("builtin:NAME[@N|@WxH]"), private to core/image.cpp and
// core/builtin_maps.cpp. Every map is a function of (u, v) with an integer number of periods per
// UV unit, evaluated at texel centres, so it tiles seamlessly at any size.
#include "core/image.hpp"

#include <string>
#include <string_view>

namespace pr::builtin {

inline constexpr std::string_view kPrefix = "builtin:";
inline constexpr int kDefaultSize = 512;

inline bool is_builtin(std::string_view spec) { return spec.substr(0, kPrefix.size()) == kPrefix; }

// `spec` is the whole "builtin:..." string; errors name it. Heights are quantized to 16 bits
// (bits = 16) so the floats the CPU samples are exactly what an R16 texture holds.
HeightField make_height(const std::string& spec, const ImageLimits& limits);
RgbaImage make_color(const std::string& spec, const ImageLimits& limits);

} // namespace pr::builtin
