#include "manyworlds/sim/video.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

extern char** environ;

namespace manyworlds::sim {
namespace {

constexpr int kMaxVideoSize = 8192;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string Errno() { return std::strerror(errno); }

// The last `max_lines` non-empty lines of a file, joined by "; ".
std::string Tail(std::FILE* file, int max_lines) {
  if (!file) return "";
  std::fflush(file);
  std::rewind(file);
  std::vector<std::string> lines;
  std::string line;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) {
    if (c == '\n' || c == '\r') {
      if (!line.empty()) lines.push_back(std::move(line));
      line.clear();
    } else {
      line.push_back(static_cast<char>(c));
    }
  }
  if (!line.empty()) lines.push_back(std::move(line));
  std::string out;
  const size_t first = lines.size() > static_cast<size_t>(max_lines) ? lines.size() - max_lines : 0;
  for (size_t i = first; i < lines.size(); ++i) out += (out.empty() ? "" : "; ") + lines[i];
  return out;
}

std::string FormatFps(double fps) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", fps);
  return buffer;
}

}  // namespace

VideoFormat VideoFormatForPath(const std::string& path) {
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  if (ext == ".png") return VideoFormat::kPng;
  if (ext == ".mp4") return VideoFormat::kMp4;
  throw ConfigError("cannot write '" + path +
                    "': the file name must end in .png (one frame) or .mp4 (H.264 video)");
}

VideoWriter::VideoWriter(std::string path, int width, int height, double fps)
    : path_(std::move(path)), format_(VideoFormatForPath(path_)), width_(width), height_(height) {
  if (width < 1 || height < 1 || width > kMaxVideoSize || height > kMaxVideoSize) {
    throw ConfigError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " is not allowed: width and height must be in [1, " +
                      std::to_string(kMaxVideoSize) + "]");
  }
  if (format_ == VideoFormat::kMp4 && (width % 2 != 0 || height % 2 != 0)) {
    throw ConfigError("an .mp4 (H.264, yuv420p) needs an even width and height, got " +
                      std::to_string(width) + "x" + std::to_string(height));
  }
  if (!(fps > 0 && fps <= 1000)) {
    throw ConfigError("frame rate " + FormatFps(fps) + " is not allowed: it must be in (0, 1000]");
  }

  // the temporary file, hidden, beside the output (rename is atomic only
  // within one file system)
  const std::filesystem::path target(path_);
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  std::string temp = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
  const int temp_fd = mkstemp(temp.data());
  if (temp_fd < 0) {
    throw Error("cannot write '" + path_ + "': cannot create a file in '" + dir.string() +
                "': " + Errno());
  }
  // ffmpeg creates the file itself, with the usual permissions (mkstemp's
  // would be 0600); the random name stays reserved for practical purposes
  close(temp_fd);
  std::remove(temp.c_str());
  temp_path_ = temp;

  log_ = std::tmpfile();
  int sockets[2];
  if (!log_ || socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0) {
    const std::string reason = Errno();
    if (log_) std::fclose(log_);
    log_ = nullptr;
    std::remove(temp_path_.c_str());
    throw Error("cannot start ffmpeg: " + reason);
  }

  std::vector<std::string> args = {"ffmpeg", "-hide_banner", "-nostdin", "-nostats",
                                   "-loglevel", "error", "-y",
                                   "-f", "rawvideo", "-pix_fmt", "rgb24",
                                   "-s", std::to_string(width) + "x" + std::to_string(height),
                                   "-r", FormatFps(fps), "-i", "pipe:0"};
  if (format_ == VideoFormat::kMp4) {
    args.insert(args.end(), {"-an", "-c:v", "libx264", "-preset", "medium", "-crf", "23",
                             "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4"});
  } else {
    args.insert(args.end(), {"-frames:v", "1", "-c:v", "png", "-f", "image2", "-update", "1"});
  }
  args.push_back(temp_path_);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sockets[1], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fileno(log_), STDERR_FILENO);
  const int rc = posix_spawnp(&pid_, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(sockets[1]);
  socket_ = sockets[0];
  if (rc != 0) {
    pid_ = -1;
    close(socket_);
    socket_ = -1;
    std::fclose(log_);
    log_ = nullptr;
    std::remove(temp_path_.c_str());
    if (rc == ENOENT) {
      throw Error("cannot write '" + path_ +
                  "': the ffmpeg program was not found on PATH; images and videos are encoded "
                  "with it (Debian: apt-get install ffmpeg)");
    }
    throw Error("cannot write '" + path_ + "': starting ffmpeg failed: " + std::strerror(rc));
  }
}

VideoWriter::~VideoWriter() {
  if (!finished_) {
    StopEncoder(/*kill_it=*/true);
    if (!temp_path_.empty()) std::remove(temp_path_.c_str());
  }
  if (log_) std::fclose(log_);
}

void VideoWriter::AddFrame(std::span<const uint8_t> rgb) {
  const size_t size = static_cast<size_t>(width_) * height_ * 3;
  if (finished_) throw Error("VideoWriter::AddFrame after Finish for '" + path_ + "'");
  if (rgb.size() != size) {
    throw Error("VideoWriter::AddFrame: got " + std::to_string(rgb.size()) + " bytes, a " +
                std::to_string(width_) + "x" + std::to_string(height_) + " RGB frame has " +
                std::to_string(size));
  }
  if (format_ == VideoFormat::kPng && frames_ > 0) {
    throw Error("'" + path_ + "' is a .png: it holds exactly one frame");
  }
  size_t done = 0;
  while (done < size) {
    const ssize_t n = send(socket_, rgb.data() + done, size - done, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      Fail("ffmpeg stopped reading frames (" + Errno() + ")");
    }
    done += static_cast<size_t>(n);
  }
  ++frames_;
}

void VideoWriter::Finish() {
  if (finished_) return;
  if (frames_ == 0) Fail("no frame was written");
  const int status = StopEncoder(/*kill_it=*/false);
  if (status != 0) {
    Fail(status < 0 ? "ffmpeg was killed" : "ffmpeg exited with status " + std::to_string(status));
  }
  // ffmpeg runs with -loglevel error, so anything it said is an error; some
  // (a failed write of the trailer on a full disk) still end with status 0
  if (const std::string log = Tail(log_, 5); !log.empty()) Fail("ffmpeg reported an error");
  // the data must be on disk before the name points at it
  const int fd = open(temp_path_.c_str(), O_RDONLY);
  if (fd < 0) Fail("ffmpeg wrote no file");
  const bool synced = fsync(fd) == 0;
  const std::string sync_error = synced ? "" : Errno();
  close(fd);
  if (!synced) Fail("cannot sync '" + temp_path_ + "': " + sync_error);
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    Fail("cannot rename the temporary file '" + temp_path_ + "': " + Errno());
  }
  finished_ = true;
}

int VideoWriter::StopEncoder(bool kill_it) {
  if (socket_ >= 0) {
    close(socket_);  // end of input: ffmpeg flushes and exits
    socket_ = -1;
  }
  if (pid_ <= 0) return -1;
  if (kill_it) kill(pid_, SIGTERM);
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void VideoWriter::Fail(const std::string& what) {
  StopEncoder(/*kill_it=*/true);
  std::string message = "writing '" + path_ + "' failed: " + what;
  if (const std::string log = Tail(log_, 5); !log.empty()) message += "; ffmpeg says: " + log;
  if (!temp_path_.empty()) std::remove(temp_path_.c_str());
  temp_path_.clear();
  finished_ = true;  // nothing left to clean up
  throw Error(message);
}

}  // namespace manyworlds::sim
