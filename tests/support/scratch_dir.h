// Per-test scratch directories in the temp dir. Each is emptied when a test
// asks for it and removed when the test program ends with every test passed;
// after a failure they stay, to be looked at.
#ifndef MANYWORLDS_TESTS_SUPPORT_SCRATCH_DIR_H_
#define MANYWORLDS_TESTS_SUPPORT_SCRATCH_DIR_H_

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace manyworlds::test_support {

namespace internal {

class ScratchCleanup : public testing::EmptyTestEventListener {
 public:
  explicit ScratchCleanup(const std::vector<std::filesystem::path>* dirs) : dirs_(dirs) {}
  void OnTestProgramEnd(const testing::UnitTest& unit_test) override {
    if (!unit_test.Passed()) return;
    for (const std::filesystem::path& dir : *dirs_) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  }

 private:
  const std::vector<std::filesystem::path>* dirs_;
};

// The directories handed out by this process; the listener that removes
// them is registered with the first one (GoogleTest owns it).
inline std::vector<std::filesystem::path>& ScratchDirs() {
  static std::vector<std::filesystem::path>* dirs = [] {
    auto* list = new std::vector<std::filesystem::path>();
    testing::UnitTest::GetInstance()->listeners().Append(new ScratchCleanup(list));
    return list;
  }();
  return *dirs;
}

}  // namespace internal

// An emptied path in the temp dir unique to this process, the test file
// (`suite`) and `name`; created only when `create` is true.
inline std::filesystem::path ScratchDir(const std::string& suite, const std::string& name,
                                        bool create) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("mw_" + suite + "_test_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  if (create) std::filesystem::create_directories(dir);
  internal::ScratchDirs().push_back(dir);
  return dir;
}

}  // namespace manyworlds::test_support

#endif  // MANYWORLDS_TESTS_SUPPORT_SCRATCH_DIR_H_
