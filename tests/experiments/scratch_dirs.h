// Directories for the experiments tests: the source tree (configs) and
// per-test scratch run directories.
#ifndef MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_
#define MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/support/scratch_dir.h"

namespace manyworlds::experiments::test_dirs {

// MANYWORLDS_SOURCE_DIR if set, else the tree the tests were built from.
inline std::filesystem::path SourceDir() {
  const char* dir = std::getenv("MANYWORLDS_SOURCE_DIR");
  return dir != nullptr ? std::filesystem::path(dir)
                        : std::filesystem::path(MANYWORLDS_TEST_SOURCE_DIR);
}

// An emptied directory path in the temp dir, unique to this process, the
// test file (`suite`) and `name`; it is not created. Removed after the
// program if every test passed.
inline std::filesystem::path Scratch(const std::string& suite, const std::string& name) {
  return test_support::ScratchDir(suite, name, /*create=*/false);
}

}  // namespace manyworlds::experiments::test_dirs

#endif  // MANYWORLDS_TESTS_EXPERIMENTS_SCRATCH_DIRS_H_
