#pragma once
// The memory the system can give a process now without swapping (Linux: MemAvailable in
// /proc/meminfo), or nothing where it does not say.
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace pr {

inline std::optional<std::uint64_t> available_memory_bytes()
{
    std::ifstream in("/proc/meminfo");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string key, unit;
        std::uint64_t value = 0;
        if (fields >> key >> value >> unit && key == "MemAvailable:" && unit == "kB") return value * 1024u;
    }
    return std::nullopt;
}

} // namespace pr
