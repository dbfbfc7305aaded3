#pragma once
// Test helper: a temporary folder of its own per test (ctest may run tests in parallel).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace prtest {

namespace fs = std::filesystem;

// Removed with everything in it when the test ends.
class TempDir {
public:
    TempDir()
    {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("pr_mesh_" + std::string(info->test_suite_name()) +
                                            "_" + info->name() + "_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    ~TempDir() { fs::remove_all(dir_); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    fs::path write(const std::string& name, const std::string& content) const
    {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary) << content;
        return p;
    }
    fs::path write_bytes(const std::string& name, const std::vector<char>& bytes) const
    {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p;
    }
    const fs::path& path() const { return dir_; }

private:
    fs::path dir_;
};

} // namespace prtest
