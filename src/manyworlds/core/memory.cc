#include "manyworlds/core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "manyworlds/core/error.h"

namespace manyworlds {

bool KeepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // 32 MiB is glibc's largest mmap threshold on 64-bit; a fixed value also
  // stops the dynamic adjustment. The trim threshold keeps up to 512 MiB of
  // free heap top before giving it back.
  const bool mmap_ok = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1;
  const bool trim_ok = mallopt(M_TRIM_THRESHOLD, 512 << 20) == 1;
  return mmap_ok && trim_ok;
#else
  return false;
#endif
}

uint64_t PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size);
}

uint64_t UsableMemoryBytes(bool* limited) {
  uint64_t usable = PhysicalMemoryBytes();
  if (limited != nullptr) *limited = false;
  for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
    rlimit limit{};
    if (getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
        (usable == 0 || limit.rlim_cur < usable)) {
      usable = limit.rlim_cur;
      if (limited != nullptr) *limited = true;
    }
  }
  return usable;
}

uint64_t ResidentBytes() {
  // /proc/self/statm: total and resident size in pages
  std::FILE* file = std::fopen("/proc/self/statm", "r");
  if (file == nullptr) return 0;
  unsigned long long size = 0, resident = 0;
  const int read = std::fscanf(file, "%llu %llu", &size, &resident);
  std::fclose(file);
  const long page_size = sysconf(_SC_PAGESIZE);
  if (read != 2 || page_size <= 0) return 0;
  return static_cast<uint64_t>(resident) * static_cast<uint64_t>(page_size);
}

void CheckMemoryEstimate(double bytes, const std::string& what, const std::string& hint) {
  bool limited = false;
  const uint64_t total = UsableMemoryBytes(&limited);
  if (total == 0 || !(bytes > static_cast<double>(total))) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char text[200];
  std::snprintf(text, sizeof(text), " needs about %.1f GiB, more than %s %.1f GiB; ", bytes / kGiB,
                limited ? "this process's memory limit (ulimit -v or -d) of" : "this machine's",
                static_cast<double>(total) / kGiB);
  throw ConfigError(what + text + "lower " + hint);
}

namespace {
// Items made before a batch's memory is projected: enough that one item's
// allocations settle, few enough that a batch that cannot fit is refused early.
constexpr int64_t kSampledItems = 16;
}  // namespace

BatchMemoryCheck::BatchMemoryCheck(int64_t count, std::string what, std::string hint)
    : count_(count), what_(std::move(what)), hint_(std::move(hint)), start_bytes_(ResidentBytes()) {}

void BatchMemoryCheck::Made(int64_t index) {
  if (index + 1 != std::min(kSampledItems, count_) || count_ <= kSampledItems) return;
  const uint64_t now = ResidentBytes();
  if (now == 0 || start_bytes_ == 0 || now <= start_bytes_) return;
  const double per_item = static_cast<double>(now - start_bytes_) / static_cast<double>(index + 1);
  CheckMemoryEstimate(static_cast<double>(now) + per_item * static_cast<double>(count_ - index - 1),
                      what_, hint_);
}

}  // namespace manyworlds
