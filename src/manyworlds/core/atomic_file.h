// Crash-safe file output for results and resolved configurations, and the one reader of
// whole files that refuses what is not a regular file.
#ifndef MANYWORLDS_CORE_ATOMIC_FILE_H_
#define MANYWORLDS_CORE_ATOMIC_FILE_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace manyworlds {

// Replaces `path` with `content` atomically: writes a temporary file in the
// same directory, fsyncs it, renames it over `path` and fsyncs the
// directory. Readers see the old file or the new one, never a partial one.
// The directory must exist, and `path`, if it exists, must be a regular
// file (a device, directory, pipe or symbolic link is never replaced).
// Throws Error naming the path on failure (the temporary file is removed).
void AtomicWriteFile(const std::filesystem::path& path, std::string_view content);

// The whole content of the regular file `path`, read without blocking: a FIFO, device or
// directory is refused before it is opened (opening a FIFO waits for a writer forever), and so
// is a file of more than `max_bytes`. Throws Error naming the path and what it is instead.
std::string ReadRegularFile(const std::filesystem::path& path,
                            std::uintmax_t max_bytes = std::uintmax_t{1} << 30);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_ATOMIC_FILE_H_
