// Process memory: the allocator setting training wants, and the check that
// a requested size fits in this machine's memory before it is allocated.
#ifndef MANYWORLDS_CORE_MEMORY_H_
#define MANYWORLDS_CORE_MEMORY_H_

#include <cstdint>
#include <string>

namespace manyworlds {

// Makes glibc keep freed blocks of up to 32 MiB for reuse instead of
// returning them to the kernel. A training update allocates and frees the
// same few-MiB activations every step; by default glibc unmaps (or trims)
// them and the next step page-faults them back in, zeroed. Measured on
// PEARL at oyster's sizes (docs/benchmarks.md): 3.4 -> 5.1 updates/s.
// Call once at program start, before threads; the CLI does. No effect (and
// returns false) where the C library is not glibc.
bool KeepFreedMemoryForReuse();

// Physical memory of this machine in bytes (0 if unknown).
uint64_t PhysicalMemoryBytes();

// The memory this process may use in bytes: the machine's physical memory,
// or the process's address-space or data limit (ulimit -v, -d) where that is
// lower (0 if unknown). `limited` tells which.
uint64_t UsableMemoryBytes(bool* limited = nullptr);

// Resident memory of this process in bytes (0 if unknown).
uint64_t ResidentBytes();

// Throws ConfigError when `bytes` exceeds the usable memory:
// "<what> needs about N GiB, more than this machine's M GiB; lower <hint>"
// (or "this process's limit of M GiB (ulimit -v)"). Sizes are estimates made
// before allocating, so a request that cannot succeed is refused with a
// message instead of being killed for memory.
void CheckMemoryEstimate(double bytes, const std::string& what, const std::string& hint);

// The memory check of a batch of items whose size is only known once made
// (envs: a MuJoCo model and data): after the first few items, projects the
// resident memory they added per item to the whole batch and refuses it
// (CheckMemoryEstimate) when it cannot fit. Call Made(k) after item k.
class BatchMemoryCheck {
 public:
  BatchMemoryCheck(int64_t count, std::string what, std::string hint);
  void Made(int64_t index);

 private:
  int64_t count_;
  std::string what_;
  std::string hint_;
  uint64_t start_bytes_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_MEMORY_H_
