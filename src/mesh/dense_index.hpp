#pragma once
// Internal to the mesh module: assigns dense ids 0, 1, 2, ... to distinct keys in insertion
// order. Open addressing over 32-bit slots that point into the dense key array, so a million
// triangles cost a few bytes per corner instead of a node per entry (std::unordered_map).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pr {

inline std::uint64_t mix64(std::uint64_t x)
{
    // splitmix64 finaliser: spreads the float bit patterns of nearby positions across the table.
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

// Key must be equality-comparable; Hash(key) returns a std::uint64_t.
template <class Key, class Hash>
class DenseIndex {
public:
    explicit DenseIndex(std::size_t expected = 16)
    {
        keys_.reserve(expected);
        std::size_t cap = 16;
        while (cap < expected * 2) cap *= 2;
        slots_.assign(cap, kEmpty);
    }

    // Returns the id of `key` and whether it was inserted now.
    std::pair<std::uint32_t, bool> insert(const Key& key)
    {
        if ((keys_.size() + 1) * 2 > slots_.size()) grow();
        const std::size_t mask = slots_.size() - 1;
        std::size_t i = std::size_t(Hash{}(key)) & mask;
        while (slots_[i] != kEmpty) {
            if (keys_[slots_[i]] == key) return {slots_[i], false};
            i = (i + 1) & mask;
        }
        const auto id = static_cast<std::uint32_t>(keys_.size());
        slots_[i] = id;
        keys_.push_back(key);
        return {id, true};
    }

    const std::vector<Key>& keys() const { return keys_; }
    std::size_t size() const { return keys_.size(); }

private:
    static constexpr std::uint32_t kEmpty = 0xffffffffu;

    void grow()
    {
        std::vector<std::uint32_t> slots(slots_.size() * 2, kEmpty);
        const std::size_t mask = slots.size() - 1;
        for (std::uint32_t id = 0; id < keys_.size(); ++id) {
            std::size_t i = std::size_t(Hash{}(keys_[id])) & mask;
            while (slots[i] != kEmpty) i = (i + 1) & mask;
            slots[i] = id;
        }
        slots_.swap(slots);
    }

    std::vector<Key> keys_;
    std::vector<std::uint32_t> slots_;
};

// Items 0 .. count - 1 grouped by a key below `key_count` (a counting sort, in time linear in both):
// the items of key k are items[start[k]] .. items[start[k + 1] - 1], in increasing order. Items
// for which `take(i)` is false are left out.
struct Buckets {
    std::vector<std::uint32_t> start, items;
};
template <class KeyOf, class Take>
Buckets bucket_by_key(std::size_t key_count, std::size_t count, KeyOf key_of, Take take)
{
    Buckets b;
    b.start.assign(key_count + 1, 0);
    for (std::size_t i = 0; i < count; ++i)
        if (take(i)) ++b.start[std::size_t(key_of(i)) + 1];
    for (std::size_t k = 0; k < key_count; ++k) b.start[k + 1] += b.start[k];
    b.items.resize(b.start[key_count]);
    std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
    for (std::size_t i = 0; i < count; ++i)
        if (take(i)) b.items[fill[std::size_t(key_of(i))]++] = std::uint32_t(i);
    return b;
}
template <class KeyOf>
Buckets bucket_by_key(std::size_t key_count, std::size_t count, KeyOf key_of)
{
    return bucket_by_key(key_count, count, key_of, [](std::size_t) { return true; });
}

} // namespace pr
