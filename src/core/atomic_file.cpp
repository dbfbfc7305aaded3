#include "core/atomic_file.hpp"

#include "core/error.hpp"
#include "core/file_kind.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <optional>
#include <pthread.h>
#include <random>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace pr {
namespace {

namespace fs = std::filesystem;

// ---- The temporaries a signal removes ----
// A signal handler may not allocate or lock, so the registry is fixed storage and lock-free
// atomics. A slot is free, claimed (its owner is filling it in) or live (a complete path the
// handler may unlink). A temporary is registered before it is created and released once renamed
// or removed: a signal in between finds the name gone, which unlink shrugs off.
enum SlotState : int { kFree, kClaimed, kLive };
struct TempSlot {
    std::atomic<int> state{kFree};
    char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots' states");
// Far more than a run stages at once (two outputs and compare's tiles, a cache entry, the
// viewer's map thread). A temporary that finds no free slot is still written, only not removed
// by a signal.
constexpr int kTempSlots = 256;
TempSlot g_temps[kTempSlots];

int register_temporary(const fs::path& tmp)
{
    const std::string& name = tmp.native();
    if (name.size() >= PATH_MAX) return -1;
    for (int i = 0; i < kTempSlots; ++i) {
        int expected = kFree;
        if (!g_temps[i].state.compare_exchange_strong(expected, kClaimed)) continue;
        std::memcpy(g_temps[i].path, name.c_str(), name.size() + 1);
        g_temps[i].state.store(kLive);
        return i;
    }
    return -1;
}

void release_temporary(int slot)
{
    if (slot >= 0) g_temps[slot].state.store(kFree);
}

// Unlinks every temporary still being written (async-signal-safe: fixed storage, unlink).
void unlink_live_temporaries()
{
    for (TempSlot& t : g_temps)
        if (t.state.load() == kLive) ::unlink(t.path);
}

// The signals that end a run, whose handler removes the temporaries: those a user or a job
// system sends (timeout's and batch systems' SIGALRM, SIGUSR1/2, SIGXCPU past `ulimit -t`,
// SIGVTALRM) as well as Ctrl-C, kill, a closed terminal and Ctrl-\ (they ended the process with
// its temporaries left; found by an exploratory session, fiftieth).
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU, SIGVTALRM};

// While commit_together() renames a run's outputs, a signal handled on another thread (the
// committing thread blocks them; llvmpipe's threads do not) is deferred to its end: the outputs
// are then both new, not one new beside one old. The committing thread raises it afterwards, or
// the handler itself if the commit ended while it looked.
// A handler that found no commit running sets g_dying first, and a commit about to start checks
// it after announcing itself: one of the two sees the other (both are sequentially consistent),
// so a commit never starts while a handler, which looked too early to see it, unlinks its
// temporaries (a new file beside an old one, found by a review with an injected delay).
std::atomic<int> g_committing{0};
std::atomic<int> g_deferred_signal{0};
std::atomic<int> g_dying{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the commit's state");

void install_handler(int sig);

void remove_temporaries_and_die(int sig)
{
    int nothing = 0;
    g_dying.compare_exchange_strong(nothing, sig);
    if (g_committing.load() != 0) {
        int none = 0; // the first signal says how the process ends
        g_deferred_signal.compare_exchange_strong(none, sig);
        // SA_RESETHAND restored the default action: a second signal now would end the process
        // between the renames. (sigaction is async-signal-safe.)
        install_handler(sig);
        if (g_committing.load() != 0) return;
    }
    unlink_live_temporaries();
    clear_status_line_in_signal_handler();
    // SA_RESETHAND has restored the default action, and the signal is blocked while its handler
    // runs: raised again, it is delivered when the handler returns, and the process dies of it
    // (the exit status says which signal, as it would have without the handler).
    ::raise(sig);
}

// ---- What an output replaces ----

fs::path folder_of(const fs::path& file)
{
    return file.parent_path().empty() ? fs::path(".") : file.parent_path();
}

// The kernel's fs.protected_symlinks rule, which our own reading of links would bypass: a link in
// a sticky folder anyone may write (/tmp) is followed only if it is ours or the folder owner's.
// Else another user's link there could point our output at any file we may write.
bool may_follow(const fs::path& link, const struct stat& link_stat)
{
    struct stat dir;
    if (::stat(folder_of(link).c_str(), &dir) != 0) return true; // (gone: nothing is written there)
    const bool shared = (dir.st_mode & S_ISVTX) && (dir.st_mode & S_IWOTH);
    return !shared || link_stat.st_uid == ::geteuid() || link_stat.st_uid == dir.st_uid;
}

// Whether `link` is one of /proc's links to a process's open file descriptors
// (/proc/PID/fd/N, /proc/PID/task/TID/fd/N): /dev/stdout, /dev/stderr and /dev/fd/N lead to
// them. Their text names the file the descriptor has open ("/tmp/run.log", "/tmp/gone.log
// (deleted)", "pipe:[N]"), which is no place to put a new file in.
bool is_descriptor_link(const fs::path& link)
{
    std::error_code ec;
    const std::string folder = fs::canonical(folder_of(link), ec).string(); // /proc/self -> /proc/PID
    if (ec || folder.rfind("/proc/", 0) != 0 || !folder.ends_with("/fd")) return false;
    const auto number = [](std::string_view s) {
        return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
    };
    const std::string_view rest(folder.data() + 6, folder.size() - 9); // "PID" or "PID/task/TID"
    const std::size_t slash = rest.find('/');
    if (slash == std::string_view::npos) return number(rest);
    return number(rest.substr(0, slash)) && rest.substr(slash, 6) == "/task/" && number(rest.substr(slash + 6));
}

// Follows the symbolic link at `path` through further links (40 at most, Linux's own limit before
// ELOOP) to what is no link, or to the first link at which stop(link, its lstat) holds, or to one
// that cannot be read; returns where it ended.
template <class Stop>
fs::path follow_links(const fs::path& path, Stop&& stop)
{
    fs::path p = path;
    for (int hops = 0; hops < 40; ++hops) {
        struct stat st;
        if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode) || stop(p, st)) return p;
        std::error_code ec;
        const fs::path to = fs::read_symlink(p, ec);
        if (ec) return p;
        p = to.is_absolute() ? to : p.parent_path() / to;
    }
    return p;
}

// The descriptor link (is_descriptor_link) on the way from `path` to the file it names, if any.
std::optional<fs::path> descriptor_link_of(const fs::path& path)
{
    bool found = false;
    const fs::path p = follow_links(path, [&found](const fs::path& link, const struct stat&) {
        return found = is_descriptor_link(link);
    });
    return found ? std::optional<fs::path>(p) : std::nullopt;
}

// The file a write to `path` replaces: `path`, or the file a symbolic link there names (through
// further links), so that the link stays a link and its target gets the content, as a shell's `>`
// does. A dangling link names the file to create (GNU cp refuses those; `>` and POSIX cp write
// them). Where a link is not followed (a loop, or may_follow() says no) the link itself is
// returned, which check_destination() refuses.
fs::path destination_of(const fs::path& path)
{
    return follow_links(path, [](const fs::path& link, const struct stat& st) { return !may_follow(link, st); });
}

// check_output_folder() for `path`, whose write replaces `target` (destination_of(path)).
// The longest name a file may have in `folder`: the file system's, at most NAME_MAX bytes (vfat's
// pathconf says 1530, six bytes a character, for 255 of them).
long name_limit(const fs::path& folder)
{
    const long max = ::pathconf(folder.c_str(), _PC_NAME_MAX);
    return max <= 0 || max > NAME_MAX ? NAME_MAX : max;
}

void check_destination(const fs::path& path, const fs::path& target)
{
    if (path.empty()) throw Error("--out", "empty file name");
    const std::string subject = path.string();
    // A file named "-" in the working folder, where many tools read standard output (found by an
    // exploratory session, thirty-sixth).
    if (subject == "-")
        throw Error(subject, "is not standard output here: every output is a file written whole and renamed into "
                             "place; name a file (./- for a file named so)");
    // What is said of the file replaced: "is a folder", or "links to real/t.png, which is a folder".
    const std::string it = target == path ? "" : "links to " + target.string() + ", which ";
    struct stat st;
    const bool replaces = ::lstat(target.c_str(), &st) == 0; // (past the checks below: a regular file, in st)
    if (replaces) {
        if (S_ISLNK(st.st_mode)) {
            if (!may_follow(target, st))
                throw Error(subject, it + "is another user's symbolic link in " + folder_of(target).string() +
                                         ", a sticky folder anyone may write: not following it");
            throw Error(subject, std::string("cannot write: ") + std::strerror(ELOOP));
        }
        if (S_ISDIR(st.st_mode)) throw Error(subject, it + "is a folder");
        if (!S_ISREG(st.st_mode))
            throw Error(subject, it + "is not a regular file (" + special_file_kind(st.st_mode) + "): refusing to replace it");
    } else if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        // A link only the kernel can follow: /dev/stdout, /proc/self/fd/N and bash's >(...) name
        // a pipe as "pipe:[N]", which is no path. Such outputs failed after the work ("cannot
        // write: No such file or directory").
        throw Error(subject, S_ISDIR(st.st_mode) ? std::string("is a folder")
                                                  : "is not a regular file (" + std::string(special_file_kind(st.st_mode)) +
                                                        "): refusing to replace it");
    }
    // /dev/stdout redirected to a file (`>> run.log`), /dev/fd/3: the rename put a new file in
    // the old one's place, so what the shell had appended before was lost, the rest of stdout went
    // to the old, unlinked file, and a deleted one came back as "gone.log (deleted)". (Pipes and
    // terminals are refused above: they are not regular files.)
    if (const std::optional<fs::path> fd = descriptor_link_of(path))
        throw Error(subject, "is an open file descriptor's link (" + fd->string() +
                                 "): an output replaces its file, it does not write to the descriptor; give the file's own name");
    // The file standard output or standard error goes to, under its own name (`--json run.log >>
    // run.log 2>&1`): replaced the same way, it kept only the report, and what the run printed went
    // to the old, unlinked file (found by an exploratory session, fifty-third).
    if (replaces)
        for (const auto& [fd, name] : {std::pair{1, "standard output"}, std::pair{2, "standard error"}}) {
            struct stat open_file;
            if (::fstat(fd, &open_file) == 0 && open_file.st_dev == st.st_dev && open_file.st_ino == st.st_ino)
                throw Error(subject, it + "is the file " + name + " goes to: an output replaces its file, and what was "
                                          "written there would be lost; name another file");
        }
    const fs::path dir = folder_of(target);
    std::error_code ec;
    // Names and paths past the system's limits fail at the rename, after the work (a 256-byte
    // name: a 40 s cone map, then "File name too long"), and a folder whose path is too long read
    // as missing (found by an exploratory session, thirty-fifth). The temporary beside it needs
    // ".t" and six digits more than the name (temporary_name).
    const long name_max = name_limit(dir);
    if (target.filename().string().size() > std::size_t(name_max))
        throw Error(subject, "cannot write: its name is " + std::to_string(target.filename().string().size()) +
                                 " bytes, more than the " + std::to_string(name_max) + " a file name may have here");
    // (The temporary's path: the folder's, "/", and at least "." and its ".tmpNNNNNN", its name
    // cut short to fit: temporary_name.)
    if (target.string().size() >= PATH_MAX || dir.string().size() + 13 >= PATH_MAX)
        throw Error(subject, "cannot write: the path is " + std::to_string(target.string().size()) +
                                 " bytes, past what the system takes (" + std::to_string(PATH_MAX - 1) +
                                 ", with room for a temporary file's name beside it)");
    if (!fs::is_directory(dir, ec))
        throw Error(subject, (target == path ? "" : "links to " + target.string() + ", but ") +
                                 (fs::exists(dir, ec) ? dir.string() + " is not a folder"
                                                      : "folder " + dir.string() + " does not exist"));
    // Before the work, not at the rename after it. (Root passes this except on a read-only file
    // system; what else fails is reported when the file is written.)
    if (::faccessat(AT_FDCWD, dir.c_str(), W_OK, AT_EACCESS) != 0)
        throw Error(subject, "cannot write in folder " + dir.string() + ": " + std::strerror(errno));
    // An immutable or append-only file or folder (chattr +i, +a) takes no rename, root or not:
    // it failed after the work, and the outputs renamed before it stayed replaced. (statx: no
    // open, no read permission needed; where a file system keeps no such attributes, none.)
    const auto fixed = [](const fs::path& p, int flags) {
        struct statx sx {};
        return ::statx(AT_FDCWD, p.c_str(), flags, 0, &sx) == 0 &&
               (sx.stx_attributes & sx.stx_attributes_mask & (STATX_ATTR_IMMUTABLE | STATX_ATTR_APPEND)) != 0;
    };
    if (fixed(target, AT_SYMLINK_NOFOLLOW)) throw Error(subject, it + "is immutable or append-only (chattr): it cannot be replaced");
    if (fixed(dir, 0)) // (a folder reached through a link: the folder's own)
        throw Error(subject, "cannot write in folder " + dir.string() + ": it is immutable or append-only (chattr)");
    // In a sticky folder (/tmp) only the file's owner, the folder's or root may replace a file:
    // the rename failed after the work ("Operation not permitted").
    struct stat folder;
    const uid_t me = ::geteuid();
    if (me != 0 && ::lstat(target.c_str(), &st) == 0 && ::stat(dir.c_str(), &folder) == 0 &&
        (folder.st_mode & S_ISVTX) && st.st_uid != me && folder.st_uid != me)
        throw Error(subject, it + "is another user's file in " + dir.string() +
                                 ", a sticky folder: only its owner may replace it");
}

// The temporary's name: ".<name>.tmpNNNNNN" beside the destination, the name cut short where the
// whole would pass the file system's limit on a name (a legal 250-byte name failed after the work:
// "File name too long"). Cache entries' names are short: their temporaries keep the whole name,
// which the cache's trim recognizes.
std::string temporary_name(const fs::path& target, unsigned number)
{
    const std::string suffix = ".tmp" + std::to_string(number % 1000000);
    long max = name_limit(folder_of(target));
    // ...and where the whole path would pass PATH_MAX (a legal 4085-byte path failed after the
    // work; check_destination leaves room for the shortest).
    const long room = long(PATH_MAX) - 1 - long(folder_of(target).string().size()) - 1;
    max = std::max(2L + long(suffix.size()), std::min(max, room));
    std::string name = "."; // (appended, not "." + ...: GCC 12 warns wrongly on that, -Wrestrict)
    const std::string file = target.filename().string();
    name += file.substr(0, std::min(file.size(), std::size_t(max) - 1 - suffix.size()));
    name += suffix;
    return name;
}

// Makes a new temporary beside `target` (temporary_name, O_EXCL: another process's of the same
// name is left alone and other digits are tried, ten at most), registered so that a signal
// removes it: its descriptor, or -errno where none could be made.
int create_temporary(const fs::path& target, fs::path& tmp, int& slot, mode_t mode)
{
    std::random_device rd;
    for (int attempt = 1;; ++attempt) {
        tmp = folder_of(target) / temporary_name(target, rd());
        slot = register_temporary(tmp); // before the file exists: a signal from now on removes it
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
        if (fd >= 0) return fd;
        const int err = errno;
        release_temporary(std::exchange(slot, -1));
        if (err != EEXIST || attempt == 10) return -err;
    }
}

} // namespace

void check_output_folder(const fs::path& path)
{
    const fs::path target = destination_of(path);
    check_destination(path, target);
    // Root passes check_destination's permission check wherever the file system is writable, but
    // some folders take no new file (/proc, /sys): the output failed at the end, after the work
    // ("cannot write: No such file or directory"; found by an exploratory session). A temporary
    // made there and removed at once finds them before it. (Others are refused by that check.)
    if (::geteuid() == 0) {
        fs::path probe;
        int slot = -1;
        const int fd = create_temporary(target, probe, slot, 0600);
        // (No such file in a folder that is there: it takes no new file; "cannot write in folder
        // /proc: No such file or directory" read as if /proc were missing.)
        if (fd == -ENOENT)
            throw Error(path.string(), "cannot write in folder " + folder_of(target).string() +
                                           ": it takes no new file (a file system such as /proc or /sys)");
        if (fd < 0)
            throw Error(path.string(), "cannot write in folder " + folder_of(target).string() + ": " + std::strerror(-fd));
        ::close(fd);
        ::unlink(probe.c_str());
        release_temporary(slot);
    }
}

StagedFile::StagedFile(fs::path path, std::span<const std::uint8_t> bytes, OldMode old_mode)
    : path_(std::move(path)), target_(old_mode == OldMode::Drop ? path_ : destination_of(path_))
{
    const std::string subject = path_.string();
    struct stat link;
    if (old_mode != OldMode::Drop || ::lstat(path_.c_str(), &link) != 0 || !S_ISLNK(link.st_mode))
        check_destination(path_, target_); // (a link the rename replaces needs no check)

    fs::path tmp;
    const int fd = create_temporary(target_, tmp, slot_, 0644);
    if (fd < 0) throw Error(subject, std::string("cannot write: ") + std::strerror(-fd));
    const auto fail = [&](int err) {
        ::close(fd);
        ::unlink(tmp.c_str());
        release_temporary(std::exchange(slot_, -1));
        throw Error(subject, std::string("cannot write: ") + std::strerror(err));
    };
    struct stat old;
    if (old_mode == OldMode::Keep && ::stat(target_.c_str(), &old) == 0 && S_ISREG(old.st_mode)) {
        // The owner and group too where we may give them (root; a group of ours); else the new
        // file is ours, as any rename by us makes it. Before fchmod: fchown clears set-id bits.
        if (::fchown(fd, old.st_uid, old.st_gid) != 0 && errno != EPERM) fail(errno);
        if (::fchmod(fd, old.st_mode & 07777) != 0) fail(errno);
    }
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

StagedFile::StagedFile(fs::path path, std::string_view text, OldMode old_mode)
    : StagedFile(std::move(path), std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), old_mode)
{
}

StagedFile::~StagedFile()
{
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
    release_temporary(slot_);
}

void StagedFile::commit()
{
    if (tmp_.empty()) return;
    const fs::path tmp = std::exchange(tmp_, {});
    // Onto the target: renaming onto a link would replace the link itself.
    const bool renamed = ::rename(tmp.c_str(), target_.c_str()) == 0;
    const int err = errno;
    if (!renamed) ::unlink(tmp.c_str());
    release_temporary(std::exchange(slot_, -1));
    if (!renamed) throw Error(path_.string(), std::string("cannot write: ") + std::strerror(err));
}

void commit_together(std::span<StagedFile* const> files)
{
    // The signals remove_temporaries_on_signals() handles, held back between the renames: blocked
    // on this thread, deferred by the handler on any other (g_committing).
    sigset_t block, old;
    sigemptyset(&block);
    for (int sig : kSignals) sigaddset(&block, sig);
    const bool blocked = ::pthread_sigmask(SIG_BLOCK, &block, &old) == 0;
    g_committing.fetch_add(1);
    if (const int sig = g_dying.load(); sig != 0) {
        // A handler is ending the process (it may not have seen this commit): rename nothing,
        // and end with it, temporaries removed.
        struct sigaction default_action {};
        default_action.sa_handler = SIG_DFL;
        sigemptyset(&default_action.sa_mask);
        ::sigaction(sig, &default_action, nullptr);
        unlink_live_temporaries();
        ::raise(sig);
        if (blocked) ::pthread_sigmask(SIG_SETMASK, &old, nullptr); // delivered here
    }
    const auto done = [&] {
        g_committing.fetch_sub(1);
        // (Delivered when the mask is restored below; the temporaries left, if a rename failed,
        // go first.)
        if (const int sig = g_deferred_signal.exchange(0); sig != 0 && g_committing.load() == 0)
            remove_temporaries_and_die(sig);
        if (blocked) ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
    };
    // Each file replaced is exchanged with its temporary (renameat2 RENAME_EXCHANGE), so the old
    // one stays under the temporary's name until every output is in place, and a rename that
    // fails after others is undone by exchanging back (a report name the system could not take
    // replaced the PNG before it, exit 1; found by an exploratory session, thirty-fifth). Where
    // the file system cannot exchange (NFS, FUSE: EINVAL), the old file is kept as a hard link
    // beside it before a plain rename; where neither can be, a plain rename, which a later
    // failure leaves done.
    enum class Kept { Nothing, Exchanged, Linked };
    struct Done {
        StagedFile* file;
        fs::path old;  // where the old file is kept (Exchanged: the temporary's name; Linked: a link)
        Kept kept;
        bool undoable; // Nothing kept: no file was there (undone by removing the new one)
    };
    std::vector<Done> renamed;
    renamed.reserve(files.size());
    std::random_device rd;
    const auto undo = [&] {
        for (auto it = renamed.rbegin(); it != renamed.rend(); ++it) {
            if (!it->undoable) continue;
            const char* target = it->file->target_.c_str();
            bool back = false;
            if (it->kept == Kept::Nothing) back = ::unlink(target) == 0 || errno == ENOENT;
            else if (it->kept == Kept::Linked) back = ::rename(it->old.c_str(), target) == 0;
            else if (::renameat2(AT_FDCWD, it->old.c_str(), AT_FDCWD, target, RENAME_EXCHANGE) == 0) {
                ::unlink(it->old.c_str()); // (the new one, back under the temporary's name)
                back = true;
            }
            if (back) {
                it->old.clear();
            } else if (!it->old.empty()) {
                // The old file stays where it is kept, and is said (found by a review: it was removed).
                warn(it->file->path_.string() + ": could not be put back as it was (" + std::strerror(errno) +
                     "); the earlier file is kept as " + it->old.string());
                it->kept = Kept::Nothing;
                it->old.clear();
            }
        }
    };
    const auto finish = [&] {
        for (Done& d : renamed) {
            if (!d.old.empty()) ::unlink(d.old.c_str()); // the old file, or its link
            release_temporary(std::exchange(d.file->slot_, -1));
        }
    };
    try {
        for (StagedFile* f : files) {
            if (f == nullptr || f->tmp_.empty()) continue;
            struct stat st;
            const bool old_there = ::lstat(f->target_.c_str(), &st) == 0 && S_ISREG(st.st_mode);
            if (old_there && ::renameat2(AT_FDCWD, f->tmp_.c_str(), AT_FDCWD, f->target_.c_str(), RENAME_EXCHANGE) == 0) {
                renamed.push_back({f, std::exchange(f->tmp_, {}), Kept::Exchanged, true});
                continue;
            }
            fs::path link;
            if (old_there)
                for (int attempt = 0; attempt < 10 && link.empty(); ++attempt) {
                    const fs::path candidate = folder_of(f->target_) / temporary_name(f->target_, rd());
                    if (::link(f->target_.c_str(), candidate.c_str()) == 0) link = candidate;
                    else if (errno != EEXIST) break;
                }
            try {
                f->commit(); // (releases its temporary's slot; a failure throws, its temporary removed)
            } catch (...) {
                if (!link.empty()) ::unlink(link.c_str());
                throw;
            }
            const Kept kept = link.empty() ? Kept::Nothing : Kept::Linked;
            renamed.push_back({f, std::move(link), kept, !old_there || kept == Kept::Linked});
        }
    } catch (...) {
        undo();
        finish();
        done();
        throw;
    }
    finish();
    done();
}

void write_file_atomic(const fs::path& path, std::span<const std::uint8_t> bytes, OldMode old_mode)
{
    StagedFile(path, bytes, old_mode).commit();
}

void write_file_atomic(const fs::path& path, std::string_view text, OldMode old_mode)
{
    StagedFile(path, text, old_mode).commit();
}

void check_png_output(const fs::path& path)
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
    // The same file, once the last link is followed (a dangling link's target need not exist yet):
    // both existing, one file by device and inode (hard links, "./a" against "a/../a"); neither,
    // the same name in one folder, the folders by device and inode, or where a folder is missing
    // too, the paths with every link in them followed (weakly_canonical). Only the last link was
    // followed, and the paths compared as written: `--out a.png --json here/a.png`, `here` a link
    // to `.`, wrote the JSON over the picture with exit 0, and `a/../t.png` with `a` a link into
    // another folder was taken for `t.png` (found by an exploratory session, thirty-third).
    const auto same = [](const fs::path& a, const fs::path& b) {
        const fs::path fa = destination_of(a), fb = destination_of(b);
        std::error_code ec;
        const bool ea = fs::exists(fa, ec), eb = fs::exists(fb, ec);
        if (ea || eb) return ea && eb && fs::equivalent(fa, fb, ec);
        const fs::path da = fs::absolute(fa, ec).parent_path(), db = fs::absolute(fb, ec).parent_path();
        if (fs::is_directory(da, ec) && fs::is_directory(db, ec))
            return fa.filename() == fb.filename() && fs::equivalent(da, db, ec);
        return fs::weakly_canonical(fa, ec) == fs::weakly_canonical(fb, ec);
    };
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const auto& [option, path] = outputs[i];
        if (path.empty()) continue;
        for (std::size_t j = 0; j < i; ++j)
            if (!outputs[j].second.empty() && same(path, outputs[j].second))
                throw Error(option, path.string() + " is also the " + outputs[j].first + " file: give two names");
        for (const auto& [in_option, in_path] : inputs)
            if (!in_path.empty() && in_path.string().rfind("builtin:", 0) != 0 && same(path, in_path))
                // ("is an input (s.json: objects[0].mesh)": "is the s.json: objects[0].mesh input" read
                // badly; found by an exploratory session, forty-third.)
                throw Error(option, path.string() + " is an input (" + in_option + "): it would be overwritten");
    }
}

namespace {

void install_handler(int sig)
{
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_die;
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    for (int s : kSignals) sigaddset(&action.sa_mask, s); // one at a time: the first says how we end
    ::sigaction(sig, &action, nullptr);
}

} // namespace

void remove_temporaries_on_signals()
{
    for (int sig : kSignals) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler != SIG_IGN) install_handler(sig);
    }
    // A write past `ulimit -f` (SIGXFSZ) or to a pipe whose reader has gone (SIGPIPE) killed the
    // process without a word, leaving its temporaries, exit 153 or 141 (Mesa's shader cache alone
    // reached the limit in a plain render; found by an exploratory session, fiftieth). Ignored,
    // the write fails instead (EFBIG, EPIPE) and the writer says so: one line and exit 1 for an
    // output or standard output, a warning for a cache entry.
    std::signal(SIGXFSZ, SIG_IGN);
    std::signal(SIGPIPE, SIG_IGN);
}

} // namespace pr
