#pragma once
// Every output is written to a temporary file in the destination's folder and renamed into
// place when complete, so an interrupted or failed run never leaves a partial file behind.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pr {

// What a write does to the file it replaces. A user's output keeps that file's permission bits
// (and its owner and group where the process may set them): someone made it 0600 for a reason,
// and a symbolic link there is written through. The cache's own entries are written afresh: one
// made unreadable would otherwise stay so, and a link in an entry's place is replaced, not
// followed (it would have pointed a rebuild at any file the user may write).
enum class OldMode { Keep, Drop };

// Writes `bytes` to `path` atomically. Throws pr::Error naming `path` on failure; on failure
// neither `path` (if it did not exist) nor a temporary file is left behind. A `path` that is a
// symbolic link is written through: its target gets the new content and the link stays a link.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes,
                       OldMode old_mode = OldMode::Keep);
void write_file_atomic(const std::filesystem::path& path, std::string_view text, OldMode old_mode = OldMode::Keep);

// A file written now under a temporary name in its destination's folder and renamed into place
// by commit(); if never committed, the destructor removes the temporary and the destination is
// untouched. A run with several outputs stages them all, then commits them, so a failure while
// writing any of them leaves every destination as it was (a user's earlier file included).
class StagedFile {
public:
    // Writes `bytes` to the temporary. Throws pr::Error naming `path`.
    StagedFile(std::filesystem::path path, std::span<const std::uint8_t> bytes, OldMode old_mode = OldMode::Keep);
    StagedFile(std::filesystem::path path, std::string_view text, OldMode old_mode = OldMode::Keep);
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;
    ~StagedFile();
    // Renames the temporary onto the destination. Throws pr::Error naming the destination.
    void commit();

private:
    std::filesystem::path path_;   // as the user named it
    std::filesystem::path target_; // what is replaced: path_, or the file a link there names
    std::filesystem::path tmp_;
    int slot_ = -1; // in the registry of temporaries the signal handler removes; -1: none
    friend void commit_together(std::span<StagedFile* const> files);
};

// Commits each of `files` (null: none), with the signals that end a run held back until all are
// renamed: a SIGTERM between two renames left a new grid beside an old report. Both outputs or
// neither: each file replaced is exchanged with its temporary (renameat2 RENAME_EXCHANGE) and
// kept there until every output is in place, and where a rename fails those before it are put
// back (a report name the system could not take replaced the PNG before it, exit 1; found by an
// exploratory session, thirty-fifth). Where the file system cannot exchange, the old file is kept
// as a hard link beside it; where neither can be, a plain rename, which a later failure leaves
// done. An old file that cannot be put back is left where it was kept, and said.
void commit_together(std::span<StagedFile* const> files);
inline void commit_together(std::initializer_list<StagedFile*> files)
{
    commit_together(std::span<StagedFile* const>(files.begin(), files.size()));
}

// Fails early (before long work) when `path` could not be written: its folder is missing or not
// writable, it names a folder, or it exists and is not a regular file (a device, a FIFO, a
// socket: renaming over it would replace, say, /dev/null). A symbolic link is judged by the file
// it names (a dangling one by that file's folder); for root, whose permission always passes, a
// temporary made in the folder and removed at once (/proc takes none). Throws pr::Error naming `path`.
void check_output_folder(const std::filesystem::path& path);

// check_output_folder() for a PNG output, which also refuses a name ending in another image
// format's extension (".jpg": the file would hold PNG data under a name that says otherwise).
void check_png_output(const std::filesystem::path& path);

// Refuses an output that is the same file as another output or as an input (the run would
// overwrite what it reads, or keep only one of two outputs). `outputs` and `inputs` pair a file
// with the option that names it; empty paths and inputs that are not files (builtin:NAME) are
// skipped. Throws pr::Error naming the later option.
using NamedPath = std::pair<std::string, std::filesystem::path>; // option, path
void check_distinct_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

// Makes SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU and SIGVTALRM
// remove every temporary file still being written (by any thread) before the process dies of the
// signal as it would have without the handler, so an interrupted run leaves no
// ".NAME.tmpNNNNNN" behind. Signals the process ignores (nohup) stay ignored. SIGXFSZ and SIGPIPE
// are ignored: a write past `ulimit -f` or into a closed pipe fails, and is reported, instead of
// ending the process. Called once by main(); unit tests call it in a child process.
void remove_temporaries_on_signals();

} // namespace pr
