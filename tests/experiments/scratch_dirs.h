// Directories for the experiments tests: the source tree (configs) and
// per-test scratch run directories.
#ifndef MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_
#define MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace manyworlds::experiments::test_dirs {

// MANYWORLDS_SOURCE_DIR if set, else the tree the tests were built from.
inline std::filesystem::path SourceDir() {
  const char* dir = std::getenv("MANYWORLDS_SOURCE_DIR");
  return dir != nullptr ? std::filesystem::path(dir)
                        : std::filesystem::path(MANYWORLDS_TEST_SOURCE_DIR);
}

// An emptied directory path in the temp dir, unique to this process, the
// test file (`suite`) and `name`; it is not created.
inline std::filesystem::path Scratch(const std::string& suite, const std::string& name) {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("mw_" + suite + "_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace manyworlds::experiments::test_dirs

#endif  // MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_
