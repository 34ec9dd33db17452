// Image and video files from raw RGB frames, encoded by the ffmpeg program
// (Debian package ffmpeg), which reads the frames on its standard input
// (-f rawvideo -pix_fmt rgb24 -s WxH -r FPS -i pipe:0).
//
//   sim::VideoWriter video("episode.mp4", 640, 480, 40);
//   for (...) video.AddFrame(rgb);   // 640 x 480 x 3 bytes, top row first
//   video.Finish();                  // episode.mp4 appears only now
//
// Formats, by the file's extension:
//   .png  exactly one frame (a still image)
//   .mp4  H.264 (libx264, yuv420p, crf 23), width and height even
// The output is atomic: ffmpeg writes a hidden temporary file in the same
// directory, which Finish() renames over `path` once ffmpeg has succeeded;
// after a failure, or without Finish(), the temporary file is removed and
// `path` is left as it was.
//
// ffmpeg is started without a shell (posix_spawnp, so any file name is
// safe) and fed through a socket written with MSG_NOSIGNAL: if it dies, the
// writer throws instead of the process receiving SIGPIPE.
#ifndef MANYWORLDS_SIM_VIDEO_H_
#define MANYWORLDS_SIM_VIDEO_H_

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <sys/types.h>

#include "manyworlds/core/error.h"

namespace manyworlds::sim {

enum class VideoFormat { kPng, kMp4 };

// The format of a file name, by extension (case-insensitive). Throws
// ConfigError for any other extension.
VideoFormat VideoFormatForPath(const std::string& path);

class VideoWriter {
 public:
  // Starts ffmpeg. Throws ConfigError for an unknown extension, a size
  // outside [1, 8192], an odd size for MP4, or fps outside (0, 1000];
  // Error if the directory is not writable or ffmpeg cannot be started
  // (the message says how to install it).
  VideoWriter(std::string path, int width, int height, double fps);
  // Without Finish(): stops ffmpeg and removes the temporary file.
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Appends a frame (width x height x 3 bytes, rows top to bottom). Throws
  // Error for a buffer of the wrong size, a second frame for PNG, or if
  // ffmpeg has stopped (with its message).
  void AddFrame(std::span<const uint8_t> rgb);

  // Ends the stream, waits for ffmpeg and moves the file into place. Throws
  // Error (with ffmpeg's message) if there was no frame or ffmpeg failed.
  void Finish();

  const std::string& path() const { return path_; }
  VideoFormat format() const { return format_; }
  int frames() const { return frames_; }

 private:
  // Closes the stream and reaps ffmpeg; returns its exit status (-1 if it
  // did not exit normally).
  int StopEncoder(bool kill_it);
  // "ffmpeg failed writing <path>: <its last message lines>".
  [[noreturn]] void Fail(const std::string& what);

  std::string path_, temp_path_;
  VideoFormat format_;
  int width_, height_;
  int frames_ = 0;
  int socket_ = -1;     // our end; ffmpeg's stdin is the other
  pid_t pid_ = -1;
  std::FILE* log_ = nullptr;  // ffmpeg's stderr
  bool finished_ = false;
};

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_VIDEO_H_
