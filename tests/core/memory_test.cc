#include "manyworlds/core/memory.h"

#include <string>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

TEST(MemoryTest, EstimatesBeyondPhysicalMemoryAreRefusedWithTheHint) {
  const uint64_t total = PhysicalMemoryBytes();
  ASSERT_GT(total, uint64_t{1} << 26);  // Linux reports it
  EXPECT_NO_THROW(CheckMemoryEstimate(static_cast<double>(total) / 2, "half", "nothing"));
  try {
    CheckMemoryEstimate(static_cast<double>(total) * 2, "a thing", "its size");
    ADD_FAILURE() << "twice the machine's memory was accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find("a thing needs about"), 0u) << what;
    EXPECT_NE(what.find("GiB; lower its size"), std::string::npos) << what;
  }
}

// AddressSanitizer replaces malloc, and its mallopt does nothing
// (scripts/sanitize.sh): gcc says so with __SANITIZE_ADDRESS__, clang with
// __has_feature(address_sanitizer).
#if defined(__SANITIZE_ADDRESS__)
#define MANYWORLDS_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MANYWORLDS_TEST_ASAN 1
#endif
#endif

#if defined(__GLIBC__)
TEST(MemoryTest, GlibcAcceptsTheAllocatorSetting) {
#if defined(MANYWORLDS_TEST_ASAN)
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's";
#endif
  EXPECT_TRUE(KeepFreedMemoryForReuse());
}
#endif

}  // namespace
}  // namespace manyworlds
