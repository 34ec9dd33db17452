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

std::string ReadRegularFile(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw Error("cannot read '" + path.string() + "': " +
                (ec ? ec.message() : std::string("no such file")));
  }
  if (!fs::is_regular_file(status)) {
    const char* kind = fs::is_directory(status) ? "a directory"
                       : fs::is_fifo(status)    ? "a pipe (FIFO)"
                       : fs::is_socket(status)  ? "a socket"
                                                : "a device or special file";
    throw Error("cannot read '" + path.string() + "': it is " + kind + ", not a regular file");
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > max_bytes) {
    throw Error("cannot read '" + path.string() + "': " + std::to_string(size) +
                " bytes, more than the " + std::to_string(max_bytes) + " allowed");
  }
  // O_NONBLOCK: a regular file never blocks, and a file swapped for a FIFO after the check
  // returns at once instead of waiting for a writer
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error("cannot read '" + path.string() + "': " + std::strerror(errno));
  std::string content;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      throw Error("cannot read '" + path.string() + "': " + std::strerror(error));
    }
    if (n == 0) break;
    content.append(buffer, static_cast<size_t>(n));
    if (content.size() > max_bytes) {
      ::close(fd);
      throw Error("cannot read '" + path.string() + "': more than the " +
                  std::to_string(max_bytes) + " bytes allowed");
    }
  }
  ::close(fd);
  return content;
}

}  // namespace manyworlds
