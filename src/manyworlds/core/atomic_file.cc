#include "manyworlds/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

[[noreturn]] void Fail(const std::filesystem::path& path, const std::string& what, int error) {
  throw Error("cannot write '" + path.string() + "': " + what + ": " + std::strerror(error));
}

}  // namespace

void AtomicWriteFile(const std::filesystem::path& path, std::string_view content) {
  if (path.filename().empty()) throw Error("cannot write '" + path.string() + "': not a file name");
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
  // the rename replaces what is at `path`: only ever a regular file, never a
  // device (/dev/full), a directory, a pipe or a link
  struct stat existing;
  if (lstat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode)) {
    throw Error("cannot write '" + path.string() +
                "': it exists and is not a regular file (a device, directory, pipe or link); "
                "give the path of a file");
  }
  std::string temp = (dir / ("." + path.filename().string() + ".tmp.XXXXXX")).string();
  const int fd = mkstemp(temp.data());
  if (fd < 0) Fail(path, "cannot create a temporary file in '" + dir.string() + "'", errno);

  // on any failure the temporary file goes, and the target stays untouched
  auto abandon = [&](const std::string& what) {
    const int error = errno;
    close(fd);
    unlink(temp.c_str());
    Fail(path, what, error);
  };
  // mkstemp creates 0600; results are meant to be shared like any other file
  if (fchmod(fd, 0644) != 0) abandon("fchmod");
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t n = write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      abandon("write");
    }
    data += n;
    left -= static_cast<size_t>(n);
  }
  if (fsync(fd) != 0) abandon("fsync");
  if (close(fd) != 0) {
    const int error = errno;
    unlink(temp.c_str());
    Fail(path, "close", error);
  }
  if (rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    unlink(temp.c_str());
    Fail(path, "rename", error);
  }
  // make the rename itself durable
  const int dir_fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    fsync(dir_fd);
    close(dir_fd);
  }
}

}  // namespace manyworlds
