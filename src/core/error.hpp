#pragma once
// Errors that reach the user as one line: "prismrelief: error: <subject>: <problem>".
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pr {

// A failure the user can act on: bad input, a resource that is missing, a GL failure.
// `subject` is the file or option at fault; `problem` says what is wrong with it.
// `detail`: lines to print after that one (a shader compiler's log), what() holds them too.
class Error : public std::runtime_error {
public:
    Error(std::string subject, std::string problem, std::string detail = {})
        : std::runtime_error(subject + ": " + problem + (detail.empty() ? "" : "\n" + detail)),
          subject_(std::move(subject)), problem_(std::move(problem)), detail_(std::move(detail))
    {
    }
    const std::string& subject() const { return subject_; }
    const std::string& problem() const { return problem_; }
    const std::string& detail() const { return detail_; }
    // The same error said under a place that names where its subject came from ("--height: a.png:
    // cannot open", "s.json: objects[1].color: builtin:nah: …").
    Error under(const std::string& place) const { return Error(place, subject_ + ": " + problem_, detail_); }

private:
    std::string subject_;
    std::string problem_;
    std::string detail_;
};

// Exit codes (contract): 0 success, 1 bad input or runtime failure, 2 bad usage.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

// Non-fatal remarks about input that is only odd (non-manifold, degenerate faces, ...):
// printed as "prismrelief: warning: ..." on stderr, once each (as one line: one_line()).
void warn(const std::string& message);
// As warn(), but said every time: what comes again after the user acts (the viewer's refusals
// and shader errors: a second P refused the same way printed nothing, and with the panel hidden
// looked ignored; found by an exploratory session, forty-ninth).
void warn_each_time(const std::string& message);

// While one lives, the warnings this thread says are held (another thread's are not: the
// viewer's cone-map builds go on beside a drop); release() says them, and where it ends
// unreleased they are dropped and forgotten (said should they come again). For work that may
// fail after its inputs warned: a dropped file the viewer refused said "no texture
// coordinates" before its error (found by an exploratory session, forty-ninth).
class ThreadWarningHold {
public:
    ThreadWarningHold();
    ~ThreadWarningHold();
    ThreadWarningHold(const ThreadWarningHold&) = delete;
    ThreadWarningHold& operator=(const ThreadWarningHold&) = delete;
    void release();

private:
    std::vector<std::string> messages_;
    std::vector<std::string>* outer_;
    bool released_ = false;
};

// Hands every warning from now on to `observer` as it is printed (the message, without the
// "prismrelief: warning: " before it), and first those printed before, in order: the viewer's
// panel log shows what stderr says (a dropped mesh's warnings reached the terminal only; thirty-
// fifth session). It runs with warn()'s lock held, on whichever thread warned: it must not warn
// and must take its own lock. An empty function stops it.
void observe_warnings(std::function<void(const std::string&)> observer);

// Warnings while a command reads and checks its inputs are held (hold_warnings, run_cli) and
// printed when the command has accepted them all (release_warnings; at the latest when it
// returns): bad input found among them is then the one line on stderr the contract gives it, not
// that line after the warnings of the inputs read before it (a mesh's "no texture coordinates"
// above a missing height map's error). A failure while they are held drops them (drop_warnings).
void hold_warnings();
void release_warnings();
void drop_warnings();

// A line kept at the foot of a terminal while work goes on and redrawn in place (a progress bar,
// app/progress.hpp) on `out`: `line` replaces the one shown, "" clears it (the cursor back at the
// line's start). A warning on stderr clears a line shown there first and draws it again after, so
// it never runs on from a bar's end (a cache warning followed "[###...###] 100%" on its line; found
// by an exploratory session). `line` must fit the terminal's width: past it the terminal wraps,
// and "\r" goes back to the start of the last row only.
void status_line(std::FILE* out, const std::string& line);
// Clears the status line shown, if any, with write() alone: for a handler of a signal that ends
// the process (atomic_file.cpp), which may not take status_line()'s lock.
void clear_status_line_in_signal_handler() noexcept;
// The terminal columns `line` takes: its UTF-8 characters, the wide ones (CJK, full-width forms,
// emoji) two each and combining marks none (counted one each, a CJK file name's progress bar
// wrapped and left a line at every redraw; found by a review, thirty-fourth session).
std::size_t display_columns(std::string_view line);
// `text` in at most `columns` columns: its start and (more of) its end around "...", cut between
// whole characters.
std::string shortened_to_columns(const std::string& text, std::size_t columns);

// `text` with its control characters written out ("\n", "\r", "\t", else "\xNN"), so that a
// message quoting a file name or a value that holds a line break stays one line on stderr; past
// kLongestLine bytes, its middle is left out (and said so).
inline constexpr std::size_t kLongestLine = 4096;
std::string one_line(std::string_view text);

} // namespace pr
