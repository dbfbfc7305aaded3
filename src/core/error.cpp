#include "core/error.hpp"

#include <cstdio>
#include <mutex>
#include <set>
#include <string>

namespace pr {

void warn(const std::string& message)
{
    static std::mutex mutex;
    static std::set<std::string> said;
    std::lock_guard lock(mutex);
    if (said.insert(message).second) std::fprintf(stderr, "prismrelief: warning: %s\n", one_line(message).c_str());
}

std::string one_line(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u != 0x7f) {
            out.push_back(c);
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out.push_back(kHex[u >> 4]);
            out.push_back(kHex[u & 15]);
        }
    }
    // A line of megabytes (a scene naming a mesh by a 5 MB path: stderr took 5 MB, 10 for a
    // built-in name said twice) keeps its start and its end, where the problem is said, cut at
    // UTF-8 character boundaries.
    if (out.size() > kLongestLine) {
        // (A UTF-8 character continues for at most 3 bytes; in bytes that are not UTF-8, cut anywhere.)
        const auto boundary = [&out](std::size_t i) {
            for (int k = 0; k < 3 && i > 0 && (static_cast<unsigned char>(out[i]) & 0xC0) == 0x80; ++k) --i;
            return i;
        };
        const std::size_t head = boundary(kLongestLine / 2), tail = boundary(out.size() - kLongestLine / 2);
        out = out.substr(0, head) + " [... " + std::to_string(tail - head) + " bytes left out ...] " + out.substr(tail);
    }
    return out;
}

} // namespace pr
