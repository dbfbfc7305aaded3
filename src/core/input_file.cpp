#include "core/input_file.hpp"

#include "core/error.hpp"
#include "core/file_kind.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

namespace pr {
namespace {

class Fd {
public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd()
    {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }

private:
    int fd_;
};

// How long a FIFO with no writer is given for one to come (see the read loop).
constexpr int kWriterWaitMs = 1000;

template <typename Container>
Container read_input(const std::string& path, const InputLimit& limit)
{
    const auto refuse = [&path](const std::string& problem) { throw Error(path, problem); };
    const std::string cap = format_byte_size(limit.max_bytes);
    const std::string folder = limit.noun.empty() ? std::string("is a folder")
                                                  : "is a folder, not " + limit.noun;

    // A look before opening, so that a device is refused without being opened (opening one can
    // have effects of its own); the fstat below, on what was opened, is the check that counts.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) refuse(folder);
        if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))
            refuse(std::string("is not a regular file (") + special_file_kind(st.st_mode) + ")");
    }

    // O_NONBLOCK: a FIFO with no writer would otherwise block in open() until one comes, forever.
    int raw = -1;
    do raw = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    while (raw < 0 && errno == EINTR);
    // "-", where many tools read standard input, and no file of that name (said "cannot open: No
    // such file or directory"; found by an exploratory session, forty-ninth).
    if (raw < 0 && errno == ENOENT && path == "-")
        refuse("is not standard input here: name a file (/dev/stdin reads standard input; ./- is a file named so)");
    if (raw < 0) refuse(std::string("cannot open: ") + std::strerror(errno));
    const Fd fd(raw);
    if (::fstat(fd.get(), &st) != 0) refuse(std::string("cannot open: ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) refuse(folder);
    const bool regular = S_ISREG(st.st_mode);
    if (!regular && !S_ISFIFO(st.st_mode))
        refuse(std::string("is not a regular file (") + special_file_kind(st.st_mode) + ")");
    // Back to blocking reads once a pipe is known to have a writer (its data may take a while to
    // come); a regular file at once.
    const auto blocking = [&] {
        const int flags = ::fcntl(fd.get(), F_GETFL);
        if (flags < 0 || ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK) != 0)
            refuse(std::string("cannot be read: ") + std::strerror(errno));
    };
    bool awaiting_writer = !regular;
    if (regular) blocking();

    const std::uint64_t size = regular && st.st_size > 0 ? std::uint64_t(st.st_size) : 0;
    if (size > limit.max_bytes)
        refuse(fmt::format("is {} ({} bytes), more than {}: {}", format_byte_size(size), size, cap,
                           limit.why));

    // Blocks, so that a pipe never holds more than the limit and one block (a vector growing by
    // doubling held both its old and new buffers, up to twice the limit). A regular file's size is
    // known: its first block holds all of it and the byte that tells its end, so it is read into
    // place with no copy (files in /proc say 0 and are read in blocks like pipes).
    constexpr std::size_t kBlock = std::size_t(1) << 20;
    constexpr std::size_t kRead = std::size_t(1) << 16; // a pipe gives at most 64 KiB a read
    std::vector<Container> blocks;
    std::uint64_t total = 0;
    try {
        for (;;) {
            if (blocks.empty() || blocks.back().size() == blocks.back().capacity()) {
                blocks.emplace_back();
                const bool whole_file = blocks.size() == 1 && size > 0;
                blocks.back().reserve(whole_file ? std::size_t(size + 1) : kBlock);
            }
            Container& block = blocks.back();
            const std::size_t old = block.size();
            const std::size_t room =
                std::min(block.capacity() - old, std::max(kRead, std::size_t(size)));
            block.resize(old + room);
            ssize_t n = 0;
            do n = ::read(fd.get(), reinterpret_cast<char*>(block.data()) + old, room);
            while (n < 0 && errno == EINTR);
            if (awaiting_writer && (n > 0 || (n < 0 && errno == EAGAIN))) {
                // Data, or a writer with none yet (EAGAIN): from now on wait for it as long as
                // it takes, as any reader of a pipe does.
                awaiting_writer = false;
                blocking();
                if (n < 0) {
                    block.resize(old);
                    continue;
                }
            }
            if (n == 0 && awaiting_writer && total == 0) {
                // No writer: none has come yet (a named FIFO whose writer is still starting:
                // `mkfifo f; producer > f & prismrelief --height f`), or the one there left
                // without writing. poll() waits for the first (Linux reports no hang-up to a
                // reader that has not seen a writer), but only so long.
                pollfd p{fd.get(), POLLIN, 0};
                int ready = 0;
                do ready = ::poll(&p, 1, kWriterWaitMs);
                while (ready < 0 && errno == EINTR);
                if (ready == 0)
                    refuse(fmt::format("is a pipe (FIFO) with nothing writing to it (no writer "
                                       "came within {} s)", kWriterWaitMs / 1000));
                block.resize(old);
                if (ready > 0 && (p.revents & POLLIN)) continue; // a writer came with data
                n = 0; // it came and went without writing: the end of the data
            }
            if (n < 0) {
                const int err = errno;
                refuse(std::string("cannot be read: ") + std::strerror(err));
            }
            block.resize(old + std::size_t(n));
            if (n == 0) break;
            total += std::uint64_t(n);
            if (total > limit.max_bytes)
                refuse(regular ? "grew past " + cap + " while it was read: " + limit.why
                               : "is a pipe that gave more than " + cap + ": " + limit.why);
        }
        if (total == 0 && !regular)
            refuse("is a pipe (FIFO) that gave no data: its writer wrote nothing");
        if (blocks.size() == 1) return std::move(blocks.front());
        Container bytes;
        bytes.reserve(std::size_t(total));
        for (Container& block : blocks) {
            bytes.insert(bytes.end(), block.begin(), block.end());
            Container().swap(block);
        }
        return bytes;
    } catch (const std::bad_alloc&) {
        refuse("not enough memory to read it (" +
               (size > 0 ? format_byte_size(size) : format_byte_size(total) + " so far") + ")");
    }
    return {};
}

} // namespace

std::string read_input_text(const std::string& path, const InputLimit& limit)
{
    return read_input<std::string>(path, limit);
}

std::vector<std::uint8_t> read_input_bytes(const std::string& path, const InputLimit& limit)
{
    return read_input<std::vector<std::uint8_t>>(path, limit);
}

std::string format_byte_size(std::uint64_t bytes)
{
    constexpr std::uint64_t kKiB = 1024, kMiB = kKiB * 1024, kGiB = kMiB * 1024;
    const auto in = [bytes](std::uint64_t unit, const char* name) {
        if (bytes % unit == 0) return fmt::format("{} {}", bytes / unit, name);
        return fmt::format("{:.1f} {}", double(bytes) / double(unit), name);
    };
    if (bytes >= kGiB) return in(kGiB, "GiB");
    if (bytes >= kMiB) return in(kMiB, "MiB");
    if (bytes >= kKiB) return in(kKiB, "KiB");
    return fmt::format("{} bytes", bytes);
}

} // namespace pr
