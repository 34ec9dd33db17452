// Crash-safe file output for results and resolved configurations.
#ifndef MANYWORLDS_CORE_ATOMIC_FILE_H_
#define MANYWORLDS_CORE_ATOMIC_FILE_H_

#include <filesystem>
#include <string_view>

namespace manyworlds {

// Replaces `path` with `content` atomically: writes a temporary file in the
// same directory, fsyncs it, renames it over `path` and fsyncs the
// directory. Readers see the old file or the new one, never a partial one.
// The directory must exist, and `path`, if it exists, must be a regular
// file (a device, directory, pipe or symbolic link is never replaced).
// Throws Error naming the path on failure (the temporary file is removed).
void AtomicWriteFile(const std::filesystem::path& path, std::string_view content);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_ATOMIC_FILE_H_
