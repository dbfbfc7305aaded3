#pragma once
// FNV-1a, 64 bits: content keys of derived data (cone-map cache entries and their checksums, the
// prism walk's merged triangles). Not for anything an adversary picks.
#include <cstddef>
#include <cstdint>

namespace pr {

struct Fnv {
    std::uint64_t h = 0xcbf29ce484222325ull;
    void add(const void* data, std::size_t n)
    {
        const auto* p = static_cast<const std::uint8_t*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    }
    void add32(std::uint32_t v) { add(&v, 4); }
};

} // namespace pr
