// What outputs may replace (no devices, FIFOs or sockets; links written through; modes kept), the
// early check of the folder, the temporaries a signal removes, and the cone-map cache's place,
// unreadable entries and stale temporaries (docs/robustness.md, "Outputs" and "Cache validation").
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "maps/conemap.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <grp.h>
#include <iterator>
#include <optional>
#include <pthread.h>
#include <string>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using namespace pr;

namespace {

std::string read_all(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool contains(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}

// What check_output_folder() says of `path`, or "" when it accepts it.
std::string refusal(const fs::path& path)
{
    try {
        check_output_folder(path);
    } catch (const Error& e) {
        return e.problem();
    }
    return {};
}

std::vector<std::string> temporaries_in(const fs::path& dir)
{
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(dir))
        if (contains(e.path().filename().string(), ".tmp")) found.push_back(e.path().filename().string());
    return found;
}

fs::perms mode_of(const fs::path& p)
{
    return fs::status(p).permissions();
}

// Runs `body` in a child process without root's powers (as nobody when we are root) and returns
// its exit status, or nullopt where no such user can be had (the caller skips). The child's
// stderr goes to `stderr_to` if given (opened before the powers are dropped).
std::optional<int> exit_status_without_root(const std::function<int()>& body, const fs::path& stderr_to = {})
{
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (!stderr_to.empty()) {
            const int fd = ::open(stderr_to.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd < 0 || ::dup2(fd, 2) < 0) ::_exit(78);
        }
        if (::geteuid() == 0 && (::setgroups(0, nullptr) != 0 || ::setgid(65534) != 0 || ::setuid(65534) != 0))
            ::_exit(77);
        ::_exit(body());
    }
    int status = 0;
    if (pid < 0 || ::waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) == 77)
        return std::nullopt;
    return WEXITSTATUS(status);
}

HeightField ramp(int w, int h)
{
    HeightField f;
    f.width = w;
    f.height = h;
    f.texels.resize(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) f.texels[std::size_t(y) * w + x] = float((x * 7 + y * 3) % 16) / 15.0f;
    return f;
}

// Sets (or, with nullptr, unsets) an environment variable for a scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name)
    {
        if (const char* old = std::getenv(name)) old_ = old;
        if (value) ::setenv(name, value, 1);
        else ::unsetenv(name);
    }
    ~ScopedEnv()
    {
        if (old_) ::setenv(name_, old_->c_str(), 1);
        else ::unsetenv(name_);
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

} // namespace

// Renaming over a FIFO, a device or a socket replaced it with a regular file (as root, --out
// /dev/null replaced the system's). They are refused by what they are, links followed, before
// anything is written (only checked for /dev/null: a regression must not replace it).
TEST(OutputSafety, SpecialFilesAreRefused)
{
    prtest::TempDir dir;
    const fs::path fifo = dir.path() / "fifo.png";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    EXPECT_EQ(refusal(fifo), "is not a regular file (a FIFO): refusing to replace it");
    EXPECT_THROW(write_file_atomic(fifo, std::string_view("x")), Error);
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_TRUE(temporaries_in(dir.path()).empty());

    EXPECT_EQ(refusal("/dev/null"), "is not a regular file (a character device): refusing to replace it");
    fs::create_symlink("/dev/null", dir.path() / "null.png");
    EXPECT_EQ(refusal(dir.path() / "null.png"),
              "links to /dev/null, which is not a regular file (a character device): refusing to replace it");

    const fs::path socket_path = dir.path() / "s.png";
    const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    ASSERT_LT(socket_path.native().size(), sizeof address.sun_path);
    std::memcpy(address.sun_path, socket_path.c_str(), socket_path.native().size() + 1);
    ASSERT_EQ(::bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    EXPECT_EQ(refusal(socket_path), "is not a regular file (a socket): refusing to replace it");
    ::close(s);

    EXPECT_EQ(refusal(dir.path()), "is a folder");
}

// A link is written through (it was replaced by a regular file, its target keeping the old
// content): the target, found through any chain of links, gets the content and its temporary
// sits next to it. A dangling link's target is created where its folder exists.
TEST(OutputSafety, LinksAreWrittenThrough)
{
    prtest::TempDir dir;
    const fs::path d = dir.path();
    fs::create_directory(d / "real");
    dir.write("real/t.png", "old");
    fs::create_symlink("real/t.png", d / "link.png");
    fs::create_symlink("link.png", d / "link2.png");
    write_file_atomic(d / "link.png", std::string_view("new"));
    EXPECT_TRUE(fs::is_symlink(d / "link.png"));
    EXPECT_EQ(read_all(d / "real/t.png"), "new");
    write_file_atomic(d / "link2.png", std::string_view("newer"));
    EXPECT_TRUE(fs::is_symlink(d / "link2.png"));
    EXPECT_TRUE(fs::is_symlink(d / "link.png"));
    EXPECT_EQ(read_all(d / "real/t.png"), "newer");
    {
        StagedFile staged(d / "link.png", std::string_view("dropped"));
        EXPECT_EQ(temporaries_in(d / "real").size(), 1u);
    }
    EXPECT_EQ(read_all(d / "real/t.png"), "newer");

    fs::create_symlink("real/n.png", d / "dangling.png");
    write_file_atomic(d / "dangling.png", std::string_view("created"));
    EXPECT_TRUE(fs::is_symlink(d / "dangling.png"));
    EXPECT_EQ(read_all(d / "real/n.png"), "created");

    fs::create_symlink("nowhere/x.png", d / "lost.png");
    EXPECT_EQ(refusal(d / "lost.png"),
              "links to " + (d / "nowhere/x.png").string() + ", but folder " + (d / "nowhere").string() +
                  " does not exist");
    fs::create_symlink("loop2", d / "loop1");
    fs::create_symlink("loop1", d / "loop2");
    EXPECT_TRUE(contains(refusal(d / "loop1"), "Too many levels of symbolic links"));
    EXPECT_TRUE(temporaries_in(d).empty());
    EXPECT_TRUE(temporaries_in(d / "real").empty());
}

// Replacing a file kept neither its mode (0600 became 0644) nor its owner.
TEST(OutputSafety, ReplacingAFileKeepsItsModeAndOwner)
{
    prtest::TempDir dir;
    const fs::path f = dir.write("o.png", "old");
    fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write);
    write_file_atomic(f, std::string_view("new"));
    EXPECT_EQ(read_all(f), "new");
    EXPECT_EQ(mode_of(f), fs::perms::owner_read | fs::perms::owner_write);

    // The cache's own entries are written afresh (0644 less the umask).
    const mode_t umask = ::umask(0);
    ::umask(umask);
    write_file_atomic(f, std::string_view("fresh"), OldMode::Drop);
    EXPECT_EQ(mode_of(f), fs::perms(0644 & ~umask));

    if (::geteuid() != 0) GTEST_SKIP() << "the owner is kept only where we may give files away (root)";
    ASSERT_EQ(::chown(f.c_str(), 65534, 65534), 0);
    write_file_atomic(f, std::string_view("theirs"));
    struct stat st;
    ASSERT_EQ(::stat(f.c_str(), &st), 0);
    EXPECT_EQ(st.st_uid, 65534u);
    EXPECT_EQ(st.st_gid, 65534u);
}

// A folder that cannot be written is refused by check_output_folder(), before the work (it failed
// only at the end). Root may write anywhere but on read-only file systems: run as nobody.
TEST(OutputSafety, UnwritableFolderIsRefusedEarly)
{
    prtest::TempDir dir;
    const fs::path ro = dir.path() / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms(0555));
    const std::optional<int> status = exit_status_without_root([&] {
        const std::string said = refusal(ro / "x.png");
        return said == "cannot write in folder " + ro.string() + ": Permission denied" ? 0 : 1;
    });
    if (!status) GTEST_SKIP() << "no user without root's powers here";
    EXPECT_EQ(*status, 0);
}

// Outputs that failed only after the work, now refused before it (fourteenth session):
// - a link only the kernel follows: /dev/stdout, /proc/self/fd/N and bash's >(...) name a pipe
//   "pipe:[N]", which is no path ("cannot write: No such file or directory");
// - a legal name of 245-255 bytes, whose temporary ".NAME.tmpNNNNNN" passed the limit on a name
//   ("File name too long"): now written, under a shortened temporary name;
// - another user's file in a sticky folder (/tmp), which only its owner may replace.
TEST(OutputSafety, PipesLongNamesAndStickyFoldersAreDecidedEarly)
{
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const fs::path pipe_path = "/proc/self/fd/" + std::to_string(fds[1]);
    if (fs::exists("/proc/self/fd"))
        EXPECT_EQ(refusal(pipe_path), "is not a regular file (a FIFO): refusing to replace it");
    ::close(fds[0]);
    ::close(fds[1]);

    prtest::TempDir dir;
    const fs::path long_name = dir.path() / (std::string(250, 'd') + ".png");
    write_file_atomic(long_name, std::string_view("content"));
    EXPECT_EQ(fs::file_size(long_name), 7u);
    EXPECT_TRUE(temporaries_in(dir.path()).empty());

    const fs::path sticky = dir.path() / "sticky";
    fs::create_directory(sticky);
    fs::permissions(sticky, fs::perms(01777));
    write_file_atomic(sticky / "theirs.png", std::string_view("theirs"));
    const std::optional<int> status = exit_status_without_root([&] {
        const std::string said = refusal(sticky / "theirs.png");
        return said == "is another user's file in " + sticky.string() +
                               ", a sticky folder: only its owner may replace it"
                   ? 0
                   : 1;
    });
    if (!status) GTEST_SKIP() << "no user without root's powers here";
    EXPECT_EQ(*status, 0);
}

// Two outputs are renamed with the signals that end a run held back (a SIGTERM between the renames
// left a new grid beside an old report); the signal mask is the caller's again afterwards.
TEST(OutputSafety, CommitTogetherRenamesAllAndRestoresTheSignalMask)
{
    prtest::TempDir dir;
    sigset_t before, after;
    ASSERT_EQ(::pthread_sigmask(SIG_SETMASK, nullptr, &before), 0);
    StagedFile a(dir.path() / "a.png", std::string_view("image"));
    StagedFile b(dir.path() / "a.json", std::string_view("report"));
    commit_together({&a, nullptr, &b});
    EXPECT_EQ(fs::file_size(dir.path() / "a.png"), 5u);
    EXPECT_EQ(fs::file_size(dir.path() / "a.json"), 6u);
    EXPECT_TRUE(temporaries_in(dir.path()).empty());
    ASSERT_EQ(::pthread_sigmask(SIG_SETMASK, nullptr, &after), 0);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) EXPECT_EQ(sigismember(&before, sig), sigismember(&after, sig));
}

// A temporary being written when SIGTERM (SIGINT, SIGHUP, SIGQUIT) came stayed behind. Now the
// handler removes every live one and the process still dies of the signal.
TEST(OutputSafetyDeathTest, SignalRemovesStagedTemporaries)
{
    prtest::TempDir dir;
    const fs::path d = dir.path();
    EXPECT_EXIT(
        {
            remove_temporaries_on_signals();
            StagedFile image(d / "a.png", std::string_view("image"));
            StagedFile report(d / "a.json", std::string_view("report"));
            if (temporaries_in(d).size() != 2) std::_Exit(1);
            std::raise(SIGTERM);
            std::_Exit(2);
        },
        ::testing::KilledBySignal(SIGTERM), "");
    EXPECT_TRUE(fs::is_empty(d));
}

// The signals a job system or a user sends besides those (timeout's SIGALRM, SIGUSR1, SIGXCPU
// past `ulimit -t`) left the temporaries too (found by an exploratory session, fiftieth).
TEST(OutputSafetyDeathTest, JobSignalsRemoveStagedTemporaries)
{
    for (const int sig : {SIGALRM, SIGUSR1, SIGUSR2, SIGVTALRM}) {
        prtest::TempDir dir;
        const fs::path d = dir.path();
        EXPECT_EXIT(
            {
                remove_temporaries_on_signals();
                StagedFile image(d / "a.png", std::string_view("image"));
                if (temporaries_in(d).size() != 1) std::_Exit(1);
                std::raise(sig);
                std::_Exit(2);
            },
            ::testing::KilledBySignal(sig), "")
            << strsignal(sig);
        EXPECT_TRUE(fs::is_empty(d)) << strsignal(sig);
    }
}

// A write past `ulimit -f` (SIGXFSZ) or into a pipe whose reader has gone (SIGPIPE) ended the
// process without a word, its temporaries left (exit 153 or 141; found by an exploratory
// session, fiftieth). They fail instead, and the writer reports it (exit code 4 here).
TEST(OutputSafetyDeathTest, WritesPastTheFileLimitOrIntoAClosedPipeFail)
{
    prtest::TempDir dir;
    const fs::path d = dir.path();
    EXPECT_EXIT(
        {
            remove_temporaries_on_signals();
            int fds[2];
            if (::pipe(fds) != 0) std::_Exit(1);
            ::close(fds[0]);
            if (::write(fds[1], "x", 1) != -1 || errno != EPIPE) std::_Exit(2);
            struct rlimit limit {};
            limit.rlim_cur = limit.rlim_max = 16;
            if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) std::_Exit(1);
            try {
                write_file_atomic(d / "big.bin", std::string(4096, 'x'));
            } catch (const pr::Error& e) {
                std::_Exit(std::string(e.what()).find("File too large") != std::string::npos ? 4 : 3);
            }
            std::_Exit(5);
        },
        ::testing::ExitedWithCode(4), "");
    EXPECT_TRUE(fs::is_empty(d));
}

// A signal that ends the run clears the status line (a progress bar) it finds on the terminal: a
// SIGINT during a cone map's build left "… 52%" there, and the shell's prompt or the next output
// ran on from it (found by an exploratory session, thirty-second).
TEST(OutputSafetyDeathTest, SignalClearsTheStatusLine)
{
    EXPECT_EXIT(
        {
            remove_temporaries_on_signals();
            status_line(stderr, "working 42%");
            std::raise(SIGINT);
            std::_Exit(2);
        },
        ::testing::KilledBySignal(SIGINT), "working 42%\r {11}\r$");
}

// A signal the process was started ignoring (nohup's SIGHUP) stays ignored.
TEST(OutputSafetyDeathTest, IgnoredSignalsStayIgnored)
{
    EXPECT_EXIT(
        {
            std::signal(SIGHUP, SIG_IGN);
            remove_temporaries_on_signals();
            std::raise(SIGHUP);
            std::_Exit(3);
        },
        ::testing::ExitedWithCode(3), "");
}

// Without an absolute XDG_CACHE_HOME or HOME there is no cache (it was /tmp/prismrelief-cache,
// shared between users; with TMPDIR missing, an error naming no file): maps are built, and
// nothing is read or written. A relative HOME is ignored as a relative XDG_CACHE_HOME is.
TEST(ConeCacheLocation, NoAbsoluteHomeOrXdgMeansNoCache)
{
    const ScopedEnv tmpdir("TMPDIR", "/nonexistent");
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
        const ScopedEnv home("HOME", "/home/someone");
        EXPECT_EQ(default_cache_dir(), fs::path("/home/someone/.cache/prismrelief"));
    }
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", "relative/xdg");
        const ScopedEnv home("HOME", "relative/home");
        EXPECT_EQ(default_cache_dir(), fs::path());
    }
    const ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
    const ScopedEnv home("HOME", nullptr);
    EXPECT_EQ(default_cache_dir(), fs::path());

    const HeightField f = ramp(16, 16);
    const ConeCacheResult r = cached_cone_map(f, ConeKind::Cone, default_cache_dir());
    EXPECT_FALSE(r.from_cache);
    EXPECT_TRUE(r.entry.empty());
    EXPECT_EQ(r.map.ratios.size(), 256u);
    EXPECT_EQ(cone_cache_entry(f, ConeKind::Cone, ConeBuildOptions{}, {}), fs::path());
    EXPECT_EQ(trim_cone_cache({}, 0), 0u);
}

// An entry that cannot be opened was "bad header"; now the warning says why.
TEST(ConeCacheLocation, UnreadableEntrySaysWhy)
{
    prtest::TempDir dir;
    const HeightField f = ramp(16, 16);
    const fs::path entry = cached_cone_map(f, ConeKind::Cone, dir.path()).entry;
    fs::permissions(entry, fs::perms::none);
    // (The cache's folders are made 0700: here, as a folder of another's made so, others may look in.)
    fs::permissions(entry.parent_path(), fs::perms::others_read | fs::perms::others_exec, fs::perm_options::add);
    const fs::path said = dir.path() / "stderr.txt";
    const std::optional<int> status = exit_status_without_root(
        [&] { return cached_cone_map(f, ConeKind::Cone, dir.path()).from_cache ? 1 : 0; }, said);
    if (!status) GTEST_SKIP() << "no user without root's powers here";
    EXPECT_EQ(*status, 0);
    const std::string text = read_all(said);
    EXPECT_TRUE(contains(text, entry.string() + ": cannot open: Permission denied; rebuilding it")) << text;
    EXPECT_FALSE(contains(text, "bad header")) << text;
}

// A SIGKILL or a crash leaves an entry's temporary behind: a trim removes those an hour old, and
// nothing that is not the cache's.
TEST(ConeCacheLocation, TrimRemovesStaleTemporaries)
{
    prtest::TempDir dir;
    fs::create_directories(dir.path() / "cone");
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(2);
    const fs::path stale = dir.write("cone/.cone-rg16-16x16-0123456789abcdef.bin.tmp123456", "x");
    const fs::path fresh = dir.write("cone/.relaxed-rg8-16x16-0123456789abcdef.bin.tmp654321", "x");
    const fs::path other = dir.write("cone/.notes.txt.tmp42", "x");
    const fs::path unlike = dir.write("cone/.cone-rg16-16x16-0123456789abcdef.bin.tmpx", "x");
    for (const fs::path& p : {stale, other, unlike}) fs::last_write_time(p, old);
    EXPECT_EQ(trim_cone_cache(dir.path(), std::uint64_t(1) << 30), 0u); // (counts entries)
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(fresh));
    EXPECT_TRUE(fs::exists(other));
    EXPECT_TRUE(fs::exists(unlike));
}
