// VideoWriter: the output appears only when ffmpeg succeeded, and a failed
// write (a full disk, injected with RLIMIT_FSIZE, which ffmpeg inherits)
// is an error that leaves neither the file nor its temporary behind.
#include "manyworlds/sim/video.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "tests/support/scratch_dir.h"

namespace manyworlds::sim {
namespace {

namespace fs = std::filesystem;

bool HaveFfmpeg() { return std::system("ffmpeg -version > /dev/null 2>&1") == 0; }

fs::path Scratch(const std::string& name) {
  return test_support::ScratchDir("video", name, /*create=*/true);
}

size_t Entries(const fs::path& dir) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// Noise compresses badly, so the file grows with every frame.
void WriteNoise(VideoWriter& video, int frames, int size) {
  Rng rng(1);
  std::vector<uint8_t> rgb(static_cast<size_t>(size * size * 3));
  for (int f = 0; f < frames; ++f) {
    for (uint8_t& c : rgb) c = static_cast<uint8_t>(rng.UniformInt(256));
    video.AddFrame(rgb);
  }
}

TEST(VideoWriterTest, TheFileAppearsOnlyOnSuccess) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  const fs::path dir = Scratch("ok");
  {
    VideoWriter video((dir / "clip.mp4").string(), 32, 32, 10);
    WriteNoise(video, 5, 32);
    EXPECT_FALSE(fs::exists(dir / "clip.mp4"));
    video.Finish();
  }
  EXPECT_GT(fs::file_size(dir / "clip.mp4"), 0u);
  EXPECT_EQ(Entries(dir), 1u);
  {
    VideoWriter abandoned((dir / "other.mp4").string(), 32, 32, 10);
    WriteNoise(abandoned, 2, 32);
  }  // no Finish: nothing appears, nothing is left
  EXPECT_EQ(Entries(dir), 1u);
  fs::remove_all(dir);
}

// Encodes 30 noise frames to dir/clip.mp4 with every file limited to
// `limit` bytes (0: no limit); returns the error, empty on success.
std::string EncodeLimited(const fs::path& dir, rlim_t limit) {
  std::signal(SIGXFSZ, SIG_IGN);  // inherited by ffmpeg: writes fail with EFBIG
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  rlimit small = old;
  if (limit > 0) small.rlim_cur = limit;
  std::string what;
  setrlimit(RLIMIT_FSIZE, &small);
  try {
    VideoWriter video((dir / "clip.mp4").string(), 128, 128, 10);
    WriteNoise(video, 30, 128);
    video.Finish();
  } catch (const Error& e) {
    what = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, SIG_DFL);
  return what;
}

TEST(VideoWriterTest, AFullDiskIsAnErrorAndLeavesNothing) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  const fs::path dir = Scratch("full");
  ASSERT_EQ(EncodeLimited(dir, 0), "");
  const auto size = static_cast<rlim_t>(fs::file_size(dir / "clip.mp4"));
  fs::remove(dir / "clip.mp4");
  // the disk fills while the frames are written: ffmpeg exits with 1
  std::string what = EncodeLimited(dir, size / 4);
  EXPECT_NE(what.find("clip.mp4"), std::string::npos) << "no error for a failed write";
  EXPECT_EQ(Entries(dir), 0u);
  // ... or only while the trailer is written: ffmpeg exits with 0 but says
  // "Error writing trailer", which must not give an unplayable file
  what = EncodeLimited(dir, size - 64);
  EXPECT_NE(what.find("clip.mp4"), std::string::npos) << "no error for a failed trailer";
  EXPECT_EQ(Entries(dir), 0u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds::sim
