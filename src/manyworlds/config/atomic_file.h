// Crash-safe file output for results and resolved configurations.
#ifndef MANYWORLDS_CONFIG_ATOMIC_FILE_H_
#define MANYWORLDS_CONFIG_ATOMIC_FILE_H_

#include <filesystem>
#include <string_view>

namespace manyworlds {

// Replaces `path` with `content` atomically: writes a temporary file in the
// same directory, fsyncs it, renames it over `path` and fsyncs the
// directory. Readers see the old file or the new one, never a partial one.
// The directory must exist. Throws Error naming the path on failure (the
// temporary file is removed).
void AtomicWriteFile(const std::filesystem::path& path, std::string_view content);

}  // namespace manyworlds

#endif  // MANYWORLDS_CONFIG_ATOMIC_FILE_H_
