#pragma once
// What a file that is neither regular nor a folder is, for messages such as "is not a regular
// file (a character device)": the input reader refuses such files, an output refuses to replace
// them.
#include <sys/stat.h>

namespace pr {

inline const char* special_file_kind(mode_t mode)
{
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

} // namespace pr
