#include "manyworlds/sim/model.h"

#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>

#include "manyworlds/core/atomic_file.h"

namespace manyworlds::sim {
namespace {

// mj_loadXML in MuJoCo 2.2.2 swaps the global error hooks while compiling,
// so concurrent loads would race on them; serialise loading.
std::mutex& LoadMutex() {
  static std::mutex mutex;
  return mutex;
}

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

void AddFile(mjVFS* vfs, std::string_view name, std::string_view contents) {
  const std::string n(name);
  const int status = mj_makeEmptyFileVFS(vfs, n.c_str(), static_cast<int>(contents.size()));
  if (status == 2) throw MujocoError("cannot load model: file '" + n + "' given twice");
  if (status != 0) throw MujocoError("cannot load model: virtual file system full at '" + n + "'");
  const int index = mj_findFileVFS(vfs, n.c_str());
  std::memcpy(vfs->filedata[index], contents.data(), contents.size());
}

std::unique_ptr<mjVFS, VfsDeleter> MakeVfs(std::string_view xml,
                                           std::span<const VirtualFile> files,
                                           std::string_view main_name) {
  // mjVFS holds fixed-size name tables (~2 MB): keep it off the stack.
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  AddFile(vfs.get(), main_name, xml);
  for (const VirtualFile& file : files) AddFile(vfs.get(), file.name, file.contents);
  return vfs;
}

// Numbers as text that parse back to the same doubles.
void AppendNumbers(std::string* out, const char* attribute, const mjtNum* values, int n) {
  if (n == 0) return;
  *out += ' ';
  *out += attribute;
  *out += "=\"";
  char number[32];
  for (int i = 0; i < n; ++i) {
    std::snprintf(number, sizeof(number), i == 0 ? "%.17g" : " %.17g", values[i]);
    *out += number;
  }
  *out += '"';
}

// The text of a file MuJoCo just wrote.
std::string ReadBack(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw MujocoError("cannot read back '" + file + "'");
  return text;
}

}  // namespace

std::string KeyframeXml(const mjModel* m, const mjData* d, std::string_view name) {
  if (m->nkey > 0) throw MujocoError("KeyframeXml: the model already has keyframes");
  std::string xml = "  <keyframe>\n    <key name=\"" + std::string(name) + "\"";
  AppendNumbers(&xml, "time", &d->time, 1);
  AppendNumbers(&xml, "qpos", d->qpos, m->nq);
  AppendNumbers(&xml, "qvel", d->qvel, m->nv);
  AppendNumbers(&xml, "act", d->act, m->na);
  AppendNumbers(&xml, "ctrl", d->ctrl, m->nu);
  AppendNumbers(&xml, "mpos", d->mocap_pos, 3 * m->nmocap);
  AppendNumbers(&xml, "mquat", d->mocap_quat, 4 * m->nmocap);
  xml += "/>\n  </keyframe>\n";
  return xml;
}

void SaveModelXml(const mjModel* model, std::string_view xml, std::span<const VirtualFile> files,
                  std::string_view main_name, const std::string& path,
                  std::string_view extra_elements) {
  InstallMujocoHandlers();
  if (model == nullptr) throw MujocoError("SaveModelXml: model is null");
  auto vfs = MakeVfs(xml, files, main_name);
  // MuJoCo writes to a private temporary file; the result reaches `path`
  // through AtomicWriteFile, which never replaces anything but a regular file
  std::string temp = (std::filesystem::temp_directory_path() / "manyworlds_mjcf_XXXXXX").string();
  const int fd = mkstemp(temp.data());
  if (fd < 0) throw MujocoError("cannot write MJCF to '" + path + "': no temporary file");
  close(fd);
  struct RemoveTemp {
    const std::string& file;
    ~RemoveTemp() { std::remove(file.c_str()); }
  } remove_temp{temp};
  char error[1024] = "";
  {
    std::lock_guard<std::mutex> lock(LoadMutex());
    ModelPtr again(mj_loadXML(std::string(main_name).c_str(), vfs.get(), error, sizeof(error)));
    if (!again) {
      throw MujocoError("cannot save model '" + std::string(main_name) + "': it does not compile: " +
                        error);
    }
    if (again->nq != model->nq || again->nbody != model->nbody || again->ngeom != model->ngeom) {
      throw MujocoError("cannot save model '" + std::string(main_name) +
                        "': the given model was not compiled from this document");
    }
    if (!mj_saveLastXML(temp.c_str(), model, error, sizeof(error))) {
      throw MujocoError("cannot write MJCF to '" + path + "': " +
                        (error[0] ? error : "mj_saveLastXML failed"));
    }
  }
  std::string text = ReadBack(temp);
  if (!extra_elements.empty()) {
    const size_t close_tag = text.rfind("</mujoco>");
    if (close_tag == std::string::npos) {
      throw MujocoError("saved MJCF for '" + path + "' has no </mujoco>");
    }
    text.insert(close_tag, std::string(extra_elements));
  }
  AtomicWriteFile(path, text);
}

ModelPtr LoadModelFromString(std::string_view xml, std::span<const VirtualFile> files,
                             std::string_view main_name) {
  InstallMujocoHandlers();
  auto vfs = MakeVfs(xml, files, main_name);

  char error[1024] = "";
  ModelPtr model;
  {
    std::lock_guard<std::mutex> lock(LoadMutex());
    model.reset(mj_loadXML(std::string(main_name).c_str(), vfs.get(), error, sizeof(error)));
  }
  if (!model) {
    throw MujocoError("cannot load model '" + std::string(main_name) + "': " +
                      (error[0] ? error : "unknown MuJoCo error"));
  }
  return model;
}

ModelPtr LoadModelFromFile(const std::string& path) {
  InstallMujocoHandlers();
  char error[1024] = "";
  ModelPtr model;
  const bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".mjb") == 0;
  {
    std::lock_guard<std::mutex> lock(LoadMutex());
    if (binary) {
      model.reset(mj_loadModel(path.c_str(), nullptr));
    } else {
      model.reset(mj_loadXML(path.c_str(), nullptr, error, sizeof(error)));
    }
  }
  if (!model) {
    throw MujocoError("cannot load model file '" + path + "': " +
                      (error[0] ? error : "unreadable or invalid file"));
  }
  return model;
}

DataPtr MakeData(const mjModel* model) {
  InstallMujocoHandlers();
  if (model == nullptr) throw MujocoError("MakeData: model is null");
  DataPtr data(mj_makeData(model));
  if (!data) throw MujocoError("MakeData: mj_makeData failed (out of memory?)");
  return data;
}

}  // namespace manyworlds::sim
