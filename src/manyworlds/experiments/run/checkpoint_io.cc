#include "manyworlds/experiments/run/checkpoint_io.h"

#include <sstream>
#include <string>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

// The first line of a (possibly multi-line) c10 error message.
std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

void WriteArchive(const std::filesystem::path& file,
                  const std::function<void(torch::serialize::OutputArchive&)>& fill) {
  // serialised in memory, then written with every error checked: torch's
  // file writer throws from its destructor on a full disk (std::terminate)
  std::ostringstream bytes;
  try {
    torch::serialize::OutputArchive archive;
    fill(archive);
    archive.save_to(bytes);
  } catch (const std::exception& e) {
    throw Error("cannot write checkpoint '" + file.string() + "': " + FirstLine(e.what()));
  }
  AtomicWriteFile(file, bytes.view());  // no copy of the archive
}

void ReadArchive(const std::filesystem::path& file,
                 const std::function<void(torch::serialize::InputArchive&)>& read) {
  if (!std::filesystem::exists(file)) {
    throw Error("checkpoint file '" + file.string() + "' is missing");
  }
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(file.string());
    read(archive);
  } catch (const Error& e) {
    throw Error("checkpoint '" + file.string() + "': " + e.what());
  } catch (const std::exception& e) {
    throw Error("checkpoint '" + file.string() + "' is corrupt or incompatible: " +
                FirstLine(e.what()));
  }
}

}  // namespace manyworlds::experiments
