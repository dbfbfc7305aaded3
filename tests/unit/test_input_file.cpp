// Input files the user names (core/input_file, and the mesh and image readers that use it):
// devices refused unread, FIFOs never waited on in open(), pipes read up to a limit, regular files
// refused by their size. A hang is what these tests guard against, so each runs under an alarm.
#include "error_of.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/input_file.hpp"
#include "mesh/mesh.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using prtest::TempDir;

// A hang ends the test binary (SIGALRM) instead of the suite's timeout.
class Watchdog {
public:
    Watchdog() { ::alarm(30); }
    ~Watchdog() { ::alarm(0); }
};

// Writing to a pipe whose reader has gone must fail with EPIPE, not kill the test.
class IgnoreSigpipe {
public:
    IgnoreSigpipe() : old_(std::signal(SIGPIPE, SIG_IGN)) {}
    ~IgnoreSigpipe() { std::signal(SIGPIPE, old_); }

private:
    void (*old_)(int);
};

using prtest::contains;
using prtest::error_of;

const pr::InputLimit kLimit{1 << 20, "a test file", "too much for a test"};

fs::path make_fifo(const TempDir& dir, const std::string& name)
{
    const fs::path p = dir.path() / name;
    if (::mkfifo(p.c_str(), 0600) != 0) ADD_FAILURE() << "mkfifo: " << std::strerror(errno);
    return p;
}

// Writes `bytes` to `fd` (as much as the reader takes) and closes it.
void write_all_and_close(int fd, std::string bytes)
{
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n <= 0) break; // EPIPE: the reader stopped
        done += std::size_t(n);
    }
    ::close(fd);
}

// A writer for a named FIFO: opens it (waiting for the reader, as a real writer does) and writes.
std::thread fifo_writer(const fs::path& fifo, std::string bytes)
{
    return std::thread([fifo, bytes = std::move(bytes)] {
        const int fd = ::open(fifo.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd >= 0) write_all_and_close(fd, bytes);
    });
}

const char* const kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";

} // namespace

TEST(InputFile, RegularFileIsReadWhole)
{
    TempDir dir;
    const std::string text = std::string("abc\0def", 7) + std::string(200000, 'x');
    const fs::path p = dir.write("a.bin", text);
    EXPECT_EQ(pr::read_input_text(p.string(), kLimit), text);
    const std::vector<std::uint8_t> bytes = pr::read_input_bytes(p.string(), kLimit);
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()), text);
    EXPECT_EQ(pr::read_input_text(dir.write("empty", "").string(), kLimit), "");
}

TEST(InputFile, FolderMissingFileAndDeviceAreRefusedByName)
{
    TempDir dir;
    const pr::Error folder = error_of([&] { pr::read_input_text(dir.path().string(), kLimit); });
    EXPECT_EQ(folder.subject(), dir.path().string());
    EXPECT_EQ(folder.problem(), "is a folder, not a test file");
    const std::string missing = (dir.path() / "missing").string();
    EXPECT_TRUE(contains(error_of([&] { pr::read_input_text(missing, kLimit); }).problem(),
                         "cannot open: No such file or directory"));
    if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
    Watchdog watchdog;
    const pr::Error zero = error_of([&] { pr::read_input_text("/dev/zero", kLimit); });
    EXPECT_EQ(zero.subject(), "/dev/zero");
    EXPECT_EQ(zero.problem(), "is not a regular file (a character device)");
}

TEST(InputFile, SocketIsRefusedByName)
{
    TempDir dir;
    const fs::path p = dir.path() / "s.sock";
    const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(s, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    ASSERT_LT(p.string().size(), sizeof addr.sun_path);
    std::strcpy(addr.sun_path, p.c_str());
    ASSERT_EQ(::bind(s, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
    EXPECT_EQ(error_of([&] { pr::read_input_text(p.string(), kLimit); }).problem(),
              "is not a regular file (a socket)");
    ::close(s);
}

TEST(InputFile, FifoWithoutWriterFailsWithinASecond)
{
    TempDir dir;
    Watchdog watchdog; // open() without O_NONBLOCK waited here forever, as the old readers did
    const fs::path fifo = make_fifo(dir, "fifo");
    const pr::Error e = error_of([&] { pr::read_input_bytes(fifo.string(), kLimit); });
    EXPECT_EQ(e.subject(), fifo.string());
    EXPECT_EQ(e.problem(), "is a pipe (FIFO) with nothing writing to it (no writer came within 1 s)");
}

TEST(InputFile, FifoWhoseWriterComesLateOrSlowlyIsRead)
{
    TempDir dir;
    Watchdog watchdog;
    const std::string text = "data from a writer that was still starting";
    // The writer opens the FIFO 0.3 s after the reader (`producer > fifo &` racing the reader).
    const fs::path fifo = make_fifo(dir, "late");
    std::thread late([fifo, text] {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        const int fd = ::open(fifo.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd >= 0) write_all_and_close(fd, text);
    });
    EXPECT_EQ(pr::read_input_text(fifo.string(), kLimit), text);
    late.join();
    // A writer that is there but takes 1.5 s to give its first byte is waited for: only a FIFO
    // with no writer at all is given up on.
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    std::thread slow([fd = fds[1], text] {
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        write_all_and_close(fd, text);
    });
    EXPECT_EQ(pr::read_input_text("/dev/fd/" + std::to_string(fds[0]), kLimit), text);
    slow.join();
    ::close(fds[0]);
}

TEST(InputFile, FifoWhoseWriterWritesNothingIsRefused)
{
    TempDir dir;
    Watchdog watchdog;
    const fs::path fifo = make_fifo(dir, "silent");
    std::thread writer = fifo_writer(fifo, "");
    const pr::Error e = error_of([&] { pr::read_input_text(fifo.string(), kLimit); });
    writer.join();
    EXPECT_EQ(e.problem(), "is a pipe (FIFO) that gave no data: its writer wrote nothing");
}

TEST(InputFile, PipeIsReadToItsEnd)
{
    // What bash's <(cat file) gives: /dev/fd/N, the read end of a pipe with a writer. More
    // than a pipe's buffer and more than one block, so the reads wait for the writer.
    Watchdog watchdog;
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    std::string text(3 << 20 | 12345, '\0');
    for (std::size_t i = 0; i < text.size(); ++i) text[i] = char(i * 7 % 251);
    std::thread writer([fd = fds[1], text] { write_all_and_close(fd, text); });
    const std::string got = pr::read_input_text("/dev/fd/" + std::to_string(fds[0]),
                                                {text.size(), "a test file", "too much"});
    writer.join();
    ::close(fds[0]);
    EXPECT_EQ(got.size(), text.size());
    EXPECT_TRUE(got == text);
}

TEST(InputFile, PipeBeyondTheLimitIsRefusedByName)
{
    Watchdog watchdog;
    IgnoreSigpipe ignore;
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    std::thread writer([fd = fds[1]] { write_all_and_close(fd, std::string(3 << 20, 'z')); });
    const std::string path = "/dev/fd/" + std::to_string(fds[0]);
    const pr::Error e = error_of([&] { pr::read_input_text(path, kLimit); });
    ::close(fds[0]); // the writer now gets EPIPE
    writer.join();
    EXPECT_EQ(e.subject(), path);
    EXPECT_EQ(e.problem(), "is a pipe that gave more than 1 MiB: too much for a test");
}

TEST(InputFile, RegularFileBeyondTheLimitIsRefusedBySize)
{
    TempDir dir;
    const fs::path p = dir.write("big", "");
    fs::resize_file(p, std::uintmax_t(5) << 30); // sparse: nothing is written, nothing read
    const pr::Error e = error_of([&] { pr::read_input_bytes(p.string(), kLimit); });
    EXPECT_EQ(e.problem(), "is 5 GiB (5368709120 bytes), more than 1 MiB: too much for a test");
}

TEST(InputFile, ByteSizes)
{
    EXPECT_EQ(pr::format_byte_size(100), "100 bytes");
    EXPECT_EQ(pr::format_byte_size(64 << 20), "64 MiB");
    EXPECT_EQ(pr::format_byte_size((576u << 20) + 1), "576.0 MiB");
    EXPECT_EQ(pr::format_byte_size(std::uint64_t(3) << 29), "1.5 GiB");
}

// ---- the readers that use it ------------------------------------------------------------------

TEST(InputFile, ImagesAreCappedByTheirPixelLimit)
{
    TempDir dir;
    const fs::path p = dir.write("big.png", "");
    fs::resize_file(p, std::uintmax_t(100) << 20);
    // 8 bytes a pixel and 64 MiB: 256 pixels allow 64 MiB and 2 KiB.
    const pr::Error e = error_of([&] { pr::load_height(p.string(), pr::ImageLimits{16, 256}); });
    EXPECT_EQ(e.problem(), "is 100 MiB (104857600 bytes), more than 64.0 MiB: the most an image "
                           "within the limit of 256 pixels can take (8 bytes a pixel, and 64 MiB)");
    // The default limits (64 Mpixel) allow 576 MiB, so 100 MiB is read and refused as no image.
    EXPECT_TRUE(contains(error_of([&] { pr::load_height(p.string()); }).problem(),
                         "not a supported image"));
    EXPECT_EQ(error_of([&] { pr::load_color(dir.write("e.png", "").string()); }).problem(),
              "is empty");
    Watchdog watchdog;
    const fs::path fifo = make_fifo(dir, "fifo.png");
    EXPECT_TRUE(contains(error_of([&] { pr::load_color(fifo.string()); }).problem(),
                         "with nothing writing to it"));
}

TEST(InputFile, MeshesAreCappedByTheirTriangleLimit)
{
    TempDir dir;
    const fs::path p = dir.write("big.obj", "");
    fs::resize_file(p, std::uintmax_t(100) << 20);
    pr::MeshOptions options;
    options.max_triangles = 1000; // 512 KB, so the 64 MiB floor applies
    const pr::Error e = error_of([&] { pr::load_mesh(p, options); });
    EXPECT_EQ(e.problem(), "is 100 MiB (104857600 bytes), more than 64 MiB: the most a mesh within "
                           "the limit of 1000 triangles can take (512 bytes a triangle, and at least "
                           "64 MiB)");
}

TEST(InputFile, MeshFifoWithoutWriterFailsWithinASecond)
{
    TempDir dir;
    Watchdog watchdog;
    for (const char* name : {"f.obj", "f.off"}) { // one reading for every format
        const fs::path fifo = make_fifo(dir, name);
        const pr::Error e = error_of([&] { pr::load_mesh(fifo); });
        EXPECT_EQ(e.subject(), fifo.string());
        EXPECT_EQ(e.problem(), "is a pipe (FIFO) with nothing writing to it (no writer came within 1 s)");
    }
}

TEST(InputFile, MeshFromAFifoIsReadOnce)
{
    // OpenMesh parses the bytes that were read and validated: it opened the file again by name,
    // which for a FIFO waited for a second writer that never came. Every format, OFF variants
    // included (the OFF reader must be told the header line of the bytes it parses).
    TempDir dir;
    Watchdog watchdog;
    const std::string binary_stl = [] {
        std::string b(80, ' ');
        const std::uint32_t count = 1;
        b.append(reinterpret_cast<const char*>(&count), 4);
        const float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
        b.append(reinterpret_cast<const char*>(tri), sizeof tri);
        b.append(2, '\0');
        return b;
    }();
    const struct {
        const char* name;
        std::string text;
        bool uvs;
    } cases[] = {
        {"a.obj", kTriangleObj, true},
        {"b.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", true},
        {"c.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", false},
        {"d.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", false},
        {"e.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nproperty float u\nproperty float v\nelement face 1\n"
                  "property list uchar int vertex_indices\nend_header\n"
                  "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
         true},
        {"f.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                  "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
         false},
        {"g.stl", binary_stl, false},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path fifo = make_fifo(dir, c.name);
        std::thread writer = fifo_writer(fifo, c.text);
        pr::PreparedMesh m;
        try {
            m = pr::load_mesh(fifo);
        } catch (const pr::Error& e) {
            ADD_FAILURE() << e.what();
        }
        writer.join();
        EXPECT_EQ(m.indices.size(), 3u);
        EXPECT_EQ(m.had_uvs, c.uvs);
    }
}

TEST(InputFile, ObjMaterialLibrariesAreNotOpened)
{
    // OpenMesh's OBJ reader opened the file an mtllib line names (relative to the OBJ's folder)
    // and read it to its end: a FIFO there hung it, /dev/zero took gigabytes. Materials are not
    // used, so those lines are now comments to it.
    TempDir dir;
    Watchdog watchdog;
    make_fifo(dir, "m.mtl");
    for (const char* line : {"mtllib m.mtl\n", "  \tmtllib m.mtl\r\n", "mtllib\tm.mtl\n"}) {
        SCOPED_TRACE(line);
        const fs::path p = dir.write("m.obj", std::string(line) + "usemtl x\n" + kTriangleObj);
        EXPECT_EQ(pr::load_mesh(p).indices.size(), 3u);
    }
}
