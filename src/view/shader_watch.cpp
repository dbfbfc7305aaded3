#include "view/shader_watch.hpp"

#include <system_error>

namespace pr::view {

ShaderWatch::ShaderWatch(std::filesystem::path dir) : dir_(std::move(dir)), times_(scan()) {}

std::map<std::string, std::filesystem::file_time_type> ShaderWatch::scan() const
{
    namespace fs = std::filesystem;
    std::map<std::string, fs::file_time_type> out;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code e2;
        if (!it->is_regular_file(e2)) continue;
        const auto t = it->last_write_time(e2);
        if (!e2) out[it->path().string()] = t;
    }
    return out;
}

bool ShaderWatch::changed()
{
    auto now = scan();
    if (now == times_) return false;
    times_ = std::move(now);
    return true;
}

} // namespace pr::view
