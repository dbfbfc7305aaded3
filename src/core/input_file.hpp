#pragma once
// Reading a file the user named (--mesh, --height, --color, --scene) into memory, whole, without
// ever hanging or reading without bound (docs/robustness.md, "Input files"):
//
// - character and block devices and sockets (/dev/zero, /dev/urandom, a terminal) are refused
//   by name before anything is read ("is not a regular file (a character device)");
// - the file is opened with O_NONBLOCK, so a FIFO with no writer opens at once instead of
//   waiting forever in open(). A pipe with a writer is then read with blocking reads (the
//   writer's data may take its time); a FIFO with none is given 1 s for one to come (a writer
//   started in the background may not have opened it yet) and then refused: "is a pipe (FIFO)
//   with nothing writing to it (no writer came within 1 s)";
// - a regular file larger than the caller's limit is refused by its size (fstat) before reading;
// - a pipe (bash's `<(cat x.png)`, a named FIFO with a writer) is read up to the limit and
//   refused, naming the file, as soon as it gives more.
//
// Every failure is a pr::Error whose subject is `path`. An empty regular file is returned empty
// (callers say "is empty" in their own words).
#include <cstdint>
#include <string>
#include <vector>

namespace pr {

struct InputLimit {
    std::uint64_t max_bytes = 0; // more than this is refused
    // What the file should have been, for "is a folder, not a scene file": "a scene file",
    // "a mesh file", "an image".
    std::string noun;
    // Why more than max_bytes is refused, after "is 80 MiB (83886080 bytes), more than 64 MiB: "
    // (a regular file) or "is a pipe that gave more than 64 MiB: ", e.g. "not a scene file".
    std::string why;
};

// The whole file as text or bytes. Throws pr::Error(path, problem).
std::string read_input_text(const std::string& path, const InputLimit& limit);
std::vector<std::uint8_t> read_input_bytes(const std::string& path, const InputLimit& limit);

// "64 MiB", "1.5 GiB", "100 bytes": sizes in messages.
std::string format_byte_size(std::uint64_t bytes);

} // namespace pr
