#include "manyworlds/core/atomic_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicWriteFileTest, WritesAndReplacesWithoutLeftovers) {
  const fs::path dir = fs::temp_directory_path() / "manyworlds_atomic_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "results.json";
  AtomicWriteFile(file, "first");
  EXPECT_EQ(Slurp(file), "first");
  AtomicWriteFile(file, "second, longer");
  EXPECT_EQ(Slurp(file), "second, longer");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(AtomicWriteFileTest, MissingDirectoryIsAnError) {
  try {
    AtomicWriteFile("/nonexistent/manyworlds/x.txt", "x");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/manyworlds/x.txt"), std::string::npos);
  }
}

TEST(AtomicWriteFileTest, NeverReplacesWhatIsNotARegularFile) {
  const fs::path dir = fs::temp_directory_path() / "manyworlds_atomic_special_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "a_directory");
  std::ofstream(dir / "target") << "kept";
  fs::create_symlink(dir / "target", dir / "link");
  for (const fs::path& special :
       {fs::path("/dev/null"), dir / "a_directory", dir / "link"}) {
    try {
      AtomicWriteFile(special, "x");
      ADD_FAILURE() << special;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(fs::is_symlink(dir / "link"));
  EXPECT_EQ(Slurp(dir / "target"), "kept");
  // nothing left behind by the refusals
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds
