#include "core/atomic_file.hpp"
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

TEST(AtomicFile, WritesAndReplaces)
{
    const fs::path dir = fs::temp_directory_path() / "pr_atomic_test";
    fs::create_directories(dir);
    const fs::path f = dir / "a.txt";
    pr::write_file_atomic(f, std::string_view("first"));
    pr::write_file_atomic(f, std::string_view("second"));
    std::ifstream in(f);
    std::string s;
    in >> s;
    EXPECT_EQ(s, "second");
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "a.txt");
    fs::remove_all(dir);
}

TEST(AtomicFile, MissingFolderIsAnErrorNamingTheFile)
{
    try {
        pr::write_file_atomic("/nonexistent-dir-pr/x.png", std::string_view("x"));
        FAIL() << "no error";
    } catch (const pr::Error& e) {
        EXPECT_EQ(e.subject(), "/nonexistent-dir-pr/x.png");
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
    }
}
