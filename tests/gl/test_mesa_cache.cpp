// Mesa's shader cache folder (platform/mesa_cache.hpp): the chain of folders Mesa makes, and
// where it would fail, why. No context: the check runs before Mesa loads.
#include "platform/mesa_cache.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using pr::mesa_shader_cache_problem;

namespace {

class MesaCache : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("pr_mesa_cache_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string problem(const std::string& home = "") const
    {
        return mesa_shader_cache_problem(
            [this](const char* name) -> const char* {
                const auto it = env_.find(name);
                return it == env_.end() ? nullptr : it->second.c_str();
            },
            home);
    }
    std::string file(const std::string& name) const
    {
        std::ofstream(dir_ / name) << "x";
        return (dir_ / name).string();
    }

    fs::path dir_;
    std::map<std::string, std::string> env_;
};

} // namespace

TEST_F(MesaCache, FolderOrFileThereOrMissingParent)
{
    env_["MESA_SHADER_CACHE_DIR"] = file("plain");
    EXPECT_EQ(problem(), (dir_ / "plain").string() + " is not a folder");
    env_["MESA_SHADER_CACHE_DIR"] = (dir_ / "missing" / "cache").string();
    EXPECT_EQ(problem(), "cannot make " + (dir_ / "missing" / "cache").string() + ": No such file or directory");
    // Makeable: nothing to say, and nothing left behind by the check.
    env_["MESA_SHADER_CACHE_DIR"] = (dir_ / "new").string();
    EXPECT_EQ(problem(), "");
    EXPECT_FALSE(fs::exists(dir_ / "new"));
    // A folder whose mesa_shader_cache is a file.
    fs::create_directories(dir_ / "used");
    std::ofstream(dir_ / "used" / "mesa_shader_cache") << "x";
    env_["MESA_SHADER_CACHE_DIR"] = (dir_ / "used").string();
    EXPECT_EQ(problem(), (dir_ / "used" / "mesa_shader_cache").string() + " is not a folder");
    fs::remove(dir_ / "used" / "mesa_shader_cache");
    fs::create_directories(dir_ / "used" / "mesa_shader_cache");
    EXPECT_EQ(problem(), "");
    // A link to nothing, or a loop of links: said as such (mkdir said "File exists"; found by an
    // exploratory session, fiftieth).
    fs::create_symlink(dir_ / "nowhere", dir_ / "dangling");
    env_["MESA_SHADER_CACHE_DIR"] = (dir_ / "dangling").string();
    EXPECT_EQ(problem(), (dir_ / "dangling").string() + " is a symbolic link to " + (dir_ / "nowhere").string() +
                             ", which does not exist");
    fs::create_symlink("loop2", dir_ / "loop1");
    fs::create_symlink("loop1", dir_ / "loop2");
    env_["MESA_SHADER_CACHE_DIR"] = (dir_ / "loop1").string();
    EXPECT_EQ(problem(), (dir_ / "loop1").string() + " is a symbolic link to loop2, which leads back to itself (a loop of links)");
}

TEST_F(MesaCache, PlacesInMesasOrder)
{
    const std::string plain = file("plain");
    // XDG_CACHE_HOME without MESA_SHADER_CACHE_DIR; MESA_GLSL_CACHE_DIR, the old name, in its place.
    env_["XDG_CACHE_HOME"] = plain;
    EXPECT_EQ(problem(), plain + " is not a folder");
    env_["MESA_GLSL_CACHE_DIR"] = dir_.string();
    EXPECT_EQ(problem(), "");
    env_["MESA_SHADER_CACHE_DIR"] = plain;
    EXPECT_EQ(problem(), plain + " is not a folder");
    // Neither: the home folder's .cache (not $HOME: Mesa reads the password database).
    env_.clear();
    std::ofstream(dir_ / ".cache") << "x";
    EXPECT_EQ(problem(dir_.string()), (dir_ / ".cache").string() + " is not a folder");
    // A home folder that is not there: Mesa goes without a cache and without a word.
    EXPECT_EQ(problem((dir_ / "nobody").string()), "");
}

TEST_F(MesaCache, TurnedOffByTheUserInMesasWords)
{
    env_["MESA_SHADER_CACHE_DIR"] = file("plain");
    for (const char* yes : {"1", "true", "Yes", "y", "T"}) {
        env_["MESA_SHADER_CACHE_DISABLE"] = yes;
        EXPECT_EQ(problem(), "") << yes;
    }
    // Not a word for true: Mesa keeps its cache on, and fails.
    for (const char* no : {"0", "false", "maybe", ""}) {
        env_["MESA_SHADER_CACHE_DISABLE"] = no;
        EXPECT_NE(problem(), "") << no;
    }
    // The old name counts only where the new one is not set.
    env_["MESA_GLSL_CACHE_DISABLE"] = "true";
    EXPECT_NE(problem(), "");
    env_.erase("MESA_SHADER_CACHE_DISABLE");
    EXPECT_EQ(problem(), "");
}
