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

#if defined(__GLIBC__)
TEST(MemoryTest, GlibcAcceptsTheAllocatorSetting) { EXPECT_TRUE(KeepFreedMemoryForReuse()); }
#endif

}  // namespace
}  // namespace manyworlds
