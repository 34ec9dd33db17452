#include "manyworlds/core/memory.h"

#include <unistd.h>

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

void CheckMemoryEstimate(double bytes, const std::string& what, const std::string& hint) {
  const uint64_t total = PhysicalMemoryBytes();
  if (total == 0 || !(bytes > static_cast<double>(total))) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char text[160];
  std::snprintf(text, sizeof(text), " needs about %.1f GiB, more than this machine's %.1f GiB; ",
                bytes / kGiB, static_cast<double>(total) / kGiB);
  throw ConfigError(what + text + "lower " + hint);
}

}  // namespace manyworlds
