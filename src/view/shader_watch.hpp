#pragma once
// Hot reload of shaders (development aid): remembers the modification times of every file under
// a folder and says when any was added, removed or changed. Polled by the viewer's frame loop.
#include <filesystem>
#include <map>
#include <string>

namespace pr::view {

class ShaderWatch {
public:
    explicit ShaderWatch(std::filesystem::path dir);
    const std::filesystem::path& dir() const { return dir_; }
    // True when the folder's files differ from the last scan (never throws; an unreadable
    // folder reads as empty).
    bool changed();

private:
    std::map<std::string, std::filesystem::file_time_type> scan() const;
    std::filesystem::path dir_;
    std::map<std::string, std::filesystem::file_time_type> times_;
};

} // namespace pr::view
