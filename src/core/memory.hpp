#pragma once
// The memory the system can give a process now without swapping (Linux: MemAvailable in
// /proc/meminfo), or less where the process's control group is limited (cgroup v2:
// memory.max less memory.current, as containers and CI runners set it, which MemAvailable does
// not see); nothing where neither says.
#include <algorithm>
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace pr {

inline std::optional<std::uint64_t> available_memory_bytes()
{
    std::optional<std::uint64_t> available;
    {
        std::ifstream in("/proc/meminfo");
        std::string line;
        while (std::getline(in, line)) {
            std::istringstream fields(line);
            std::string key, unit;
            std::uint64_t value = 0;
            if (fields >> key >> value >> unit && key == "MemAvailable:" && unit == "kB") {
                available = value * 1024u;
                break;
            }
        }
    }
    // (A process in the root group, or with no limit, reads "max" or nothing.)
    std::uint64_t limit = 0, used = 0;
    std::ifstream max_file("/sys/fs/cgroup/memory.max"), current_file("/sys/fs/cgroup/memory.current");
    if (max_file >> limit && current_file >> used) {
        const std::uint64_t left = limit > used ? limit - used : 0;
        available = available ? std::min(*available, left) : left;
    }
    return available;
}

} // namespace pr
