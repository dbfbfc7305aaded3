#pragma once
// What a file that is neither regular nor a folder is, for messages such as "is not a regular
// file (a character device)": the input reader refuses such files, an output refuses to replace
// them.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <string>

namespace pr {

inline const char* special_file_kind(mode_t mode)
{
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

// Why `path`, which exists, cannot be read as a file ("is a folder", "is not a regular file (a
// FIFO)"); empty for a regular file or a path that does not exist (the caller's own open says
// that). For the developer variables that name files (a FIFO there would hang a reader or
// dlopen).
inline std::string not_a_file_reason(const char* path)
{
    struct stat st {};
    if (stat(path, &st) != 0 || S_ISREG(st.st_mode)) return {};
    if (S_ISDIR(st.st_mode)) return "is a folder";
    return std::string("is not a regular file (") + special_file_kind(st.st_mode) + ")";
}

// Where `path` is a symbolic link that leads nowhere, what it is: "is a symbolic link to T,
// which does not exist" or "…, which leads back to itself (a loop of links)"; empty where it is
// no such link. For the folders a cache makes: mkdir says "File exists" of a link to nothing.
inline std::string broken_link_reason(const std::string& path)
{
    struct stat st {};
    if (lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode) || stat(path.c_str(), &st) == 0) return {};
    const bool loop = errno == ELOOP;
    char target[PATH_MAX];
    const ssize_t n = readlink(path.c_str(), target, sizeof target);
    return "is a symbolic link to " + (n >= 0 ? std::string(target, std::size_t(n)) : std::string("?")) +
           (loop ? ", which leads back to itself (a loop of links)" : ", which does not exist");
}

} // namespace pr
