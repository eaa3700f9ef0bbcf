#include "taskmatrix/mujoco/mujoco_handles.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::mujoco {

using core::InputError;

namespace {

void on_mujoco_error(const char* msg) {
  std::fprintf(stderr, "taskmatrix: MuJoCo error: %s\n", msg);
  std::fflush(stderr);
  std::_Exit(3);
}

void on_mujoco_warning(const char* msg) {
  std::fprintf(stderr, "taskmatrix: MuJoCo warning: %s\n", msg);
}

// MuJoCo's parser reports "Error: ... Element 'x', line 12" over several lines; keep one.
std::string one_line(const char* text) {
  std::string s(text);
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

}  // namespace

std::recursive_mutex& mujoco_loader_mutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

void install_mujoco_error_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = on_mujoco_error;
    mju_user_warning = on_mujoco_warning;
  });
}

ModelPtr compile_mjcf_text(const std::string& xml, const std::string& label) {
  install_mujoco_error_handlers();
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "taskmatrix_scene.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    throw InputError(label, "", "cannot create MuJoCo's in-memory file");
  }
  const int index = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[index], xml.data(), xml.size());
  char error[1024] = "";
  std::lock_guard<std::recursive_mutex> lock(mujoco_loader_mutex());
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof error);
  if (!m) throw InputError(label, "", "MuJoCo cannot compile the model: " + one_line(error));
  if (error[0] != '\0') {
    mj_deleteModel(m);
    throw InputError(label, "", "MuJoCo warns while compiling: " + one_line(error));
  }
  return ModelPtr(m);
}

ModelPtr compile_file(const std::string& path) {
  install_mujoco_error_handlers();
  char error[1024] = "";
  std::lock_guard<std::recursive_mutex> lock(mujoco_loader_mutex());
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  if (!m) throw InputError(path, "", "MuJoCo cannot compile the model: " + one_line(error));
  if (error[0] != '\0') {
    mj_deleteModel(m);
    throw InputError(path, "", "MuJoCo warns while compiling: " + one_line(error));
  }
  return ModelPtr(m);
}

ModelPtr copy_model(const mjModel* m) { return ModelPtr(mj_copyModel(nullptr, m)); }

DataPtr make_data(const mjModel* m) { return DataPtr(mj_makeData(m)); }

}  // namespace taskmatrix::mujoco
