#include "core/atomic_file.hpp"

#include "core/error.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <string>
#include <unistd.h>

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

void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes)
{
    namespace fs = std::filesystem;
    const std::string subject = path.string();
    check_output_folder(path);
    fs::path dir = path.parent_path();
    if (dir.empty()) dir = ".";

    std::random_device rd;
    std::string name = "."; // (appended, not "." + ...: GCC 12 warns wrongly on that, -Wrestrict)
    name += path.filename().string();
    name += ".tmp" + std::to_string(rd() % 1000000);
    const fs::path tmp = dir / name;
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw Error(subject, std::string("cannot write: ") + std::strerror(errno));
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            throw Error(subject, std::string("cannot write: ") + std::strerror(err));
        }
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        const int err = errno;
        ::close(fd);
        ::unlink(tmp.c_str());
        throw Error(subject, std::string("cannot write: ") + std::strerror(err));
    }
    ::close(fd);
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        throw Error(subject, std::string("cannot write: ") + std::strerror(err));
    }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view text)
{
    write_file_atomic(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

void write_second_output(const std::filesystem::path& path, std::string_view text, const std::filesystem::path& first)
{
    try {
        write_file_atomic(path, text);
    } catch (...) {
        if (!first.empty()) {
            std::error_code ignored;
            std::filesystem::remove(first, ignored);
        }
        throw;
    }
}

} // namespace pr
