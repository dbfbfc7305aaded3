#pragma once
// Errors that reach the user as one line: "prismrelief: error: <subject>: <problem>".
#include <stdexcept>
#include <string>

namespace pr {

// A failure the user can act on: bad input, a resource that is missing, a GL failure.
// `subject` is the file or option at fault; `problem` says what is wrong with it.
class Error : public std::runtime_error {
public:
    Error(std::string subject, std::string problem)
        : std::runtime_error(subject + ": " + problem), subject_(std::move(subject)),
          problem_(std::move(problem))
    {
    }
    const std::string& subject() const { return subject_; }
    const std::string& problem() const { return problem_; }

private:
    std::string subject_;
    std::string problem_;
};

// Exit codes (contract): 0 success, 1 bad input or runtime failure, 2 bad usage.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

// Non-fatal remarks about input that is only odd (non-manifold, degenerate faces, ...):
// printed as "prismrelief: warning: ..." on stderr, once each.
void warn(const std::string& message);

} // namespace pr
