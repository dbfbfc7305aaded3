#pragma once
// What a file that is neither regular nor a folder is, for messages such as "is not a regular
// file (a character device)": the input reader refuses such files, an output refuses to replace
// them.
#include <sys/stat.h>

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

} // namespace pr
