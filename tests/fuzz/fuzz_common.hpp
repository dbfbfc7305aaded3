#pragma once
// Shared by the libFuzzer harnesses: the loaders under test read files by path (OpenMesh opens
// the file itself), so each input is written to one temporary file per process and extension.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace pr::fuzz {

inline std::filesystem::path scratch_file(const std::string& extension)
{
    static const std::filesystem::path dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        std::filesystem::path d = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
                                  ("prismrelief-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir / ("input" + extension);
}

// Writes the bytes; aborts (a finding in the harness, not in the code under test) on failure.
inline void write_bytes(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size)
{
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
        std::perror(path.c_str());
        std::abort();
    }
}

} // namespace pr::fuzz
