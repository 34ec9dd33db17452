// FNV-1a, 64 bits: a hash that is the same on every platform and run (std::hash is not), for
// seeds derived from names, digests of observations and cache keys. Not for adversaries.
#ifndef MANYWORLDS_CORE_HASH_H_
#define MANYWORLDS_CORE_HASH_H_

#include <cstddef>
#include <cstdint>

namespace manyworlds {

inline constexpr uint64_t kFnv1aOffset = 14695981039346656037ULL;

// Folds `bytes` bytes at `data` into `hash` (start from kFnv1aOffset; chain calls to hash
// several ranges as one).
inline uint64_t Fnv1a(const void* data, size_t bytes, uint64_t hash = kFnv1aOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    hash ^= p[i];
    hash *= 1099511628211ULL;
  }
  return hash;
}

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_HASH_H_
