#include "core/atomic_file.hpp"

#include "core/error.hpp"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <string>
#include <unistd.h>
#include <utility>

namespace pr {

void check_output_folder(const std::filesystem::path& path)
{
    namespace fs = std::filesystem;
    if (path.empty()) throw Error("--out", "empty file name");
    fs::path dir = path.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(path.string(), "folder " + dir.string() + " does not exist");
    if (fs::is_directory(path, ec)) throw Error(path.string(), "is a folder");
}

StagedFile::StagedFile(std::filesystem::path path, std::span<const std::uint8_t> bytes) : path_(std::move(path))
{
    namespace fs = std::filesystem;
    const std::string subject = path_.string();
    check_output_folder(path_);
    fs::path dir = path_.parent_path();
    if (dir.empty()) dir = ".";

    std::random_device rd;
    std::string name = "."; // (appended, not "." + ...: GCC 12 warns wrongly on that, -Wrestrict)
    name += path_.filename().string();
    name += ".tmp" + std::to_string(rd() % 1000000);
    const fs::path tmp = dir / name;
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw Error(subject, std::string("cannot write: ") + std::strerror(errno));
    const auto fail = [&](int err) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw Error(subject, std::string("cannot write: ") + std::strerror(err));
    };
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            fail(errno);
        }
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) fail(errno);
    ::close(fd);
    tmp_ = tmp;
}

StagedFile::StagedFile(std::filesystem::path path, std::string_view text)
    : StagedFile(std::move(path), std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()))
{
}

StagedFile::~StagedFile()
{
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
}

void StagedFile::commit()
{
    if (tmp_.empty()) return;
    const std::filesystem::path tmp = std::exchange(tmp_, {});
    if (::rename(tmp.c_str(), path_.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        throw Error(path_.string(), std::string("cannot write: ") + std::strerror(err));
    }
}

void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes)
{
    StagedFile(path, bytes).commit();
}

void write_file_atomic(const std::filesystem::path& path, std::string_view text)
{
    StagedFile(path, text).commit();
}

void check_png_output(const std::filesystem::path& path)
{
    check_output_folder(path);
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* other : {".jpg", ".jpeg", ".bmp", ".tga", ".gif", ".tif", ".tiff", ".webp", ".exr", ".hdr", ".ppm"})
        if (ext == other)
            throw Error(path.string(), "only PNG images are written, and '" + path.extension().string() +
                                           "' names another format (use .png, or no extension)");
}

void check_distinct_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs)
{
    namespace fs = std::filesystem;
    // The same file: equal once made absolute and normal, or (both existing) one file by
    // device and inode (links, "./a" against "a/../a").
    const auto same = [](const fs::path& a, const fs::path& b) {
        std::error_code ec;
        if (fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal()) return true;
        return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
    };
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const auto& [option, path] = outputs[i];
        if (path.empty()) continue;
        for (std::size_t j = 0; j < i; ++j)
            if (!outputs[j].second.empty() && same(path, outputs[j].second))
                throw Error(option, path.string() + " is also the " + outputs[j].first + " file: give two names");
        for (const auto& [in_option, in_path] : inputs)
            if (!in_path.empty() && in_path.string().rfind("builtin:", 0) != 0 && same(path, in_path))
                throw Error(option, path.string() + " is the " + in_option + " input: it would be overwritten");
    }
}

} // namespace pr
