// ctest runs each test in its own process, two at a time (-j2), and several
// fixtures write their files under ::testing::TempDir() with fixed names: two
// processes of one suite would rewrite a file the other is reading (seen as
// a rare failure of Volumes.*). gtest takes TempDir() from TEST_TMPDIR, so
// each test process gets a directory of its own, removed when it exits.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

struct PerProcessTempDir {
  std::filesystem::path dir;
  PerProcessTempDir() {
    const char* base = std::getenv("TEST_TMPDIR");
    dir = std::filesystem::path(base && *base ? base : "/tmp") / ("dtm_tests_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    ::setenv("TEST_TMPDIR", (dir.string() + "/").c_str(), 1);
  }
  ~PerProcessTempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

const PerProcessTempDir temp_dir;

}  // namespace
