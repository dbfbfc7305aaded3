#pragma once
// Every output is written to a temporary file in the destination's folder and renamed into
// place when complete, so an interrupted or failed run never leaves a partial file behind.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string_view>

namespace pr {

// Writes `bytes` to `path` atomically. Throws pr::Error naming `path` on failure; on failure
// neither `path` (if it did not exist) nor a temporary file is left behind.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
void write_file_atomic(const std::filesystem::path& path, std::string_view text);

// The second output of a run that writes two (an image, then its JSON report): writes `text` to
// `path` atomically and, if that fails, removes `first` (already written) before rethrowing, so
// the run leaves both files or neither. An empty `first` is ignored.
void write_second_output(const std::filesystem::path& path, std::string_view text, const std::filesystem::path& first);

// Fails early (before long work) when `path` could not be written: its folder is missing or it
// names a folder. Throws pr::Error naming `path`.
void check_output_folder(const std::filesystem::path& path);

} // namespace pr
