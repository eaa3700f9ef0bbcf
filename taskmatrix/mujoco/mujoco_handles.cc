#include "taskmatrix/mujoco/mujoco_handles.h"

#include <mujoco/mjxmacro.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <mutex>
#include <type_traits>

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

// MuJoCo's parser takes "nan" and "inf" for any number (and overflows like 1e999 to inf), and
// its compiler passes them on: a model with one is refused, naming the field.
std::string non_finite_field(const mjModel* m) {
  auto check = [](const char* name, const auto* values, long count) -> std::string {
    for (long i = 0; i < count; ++i) {
      if (!std::isfinite(static_cast<double>(values[i]))) {
        return std::string(name) + "[" + std::to_string(i) + "]";
      }
    }
    return "";
  };
  std::string bad;
  MJMODEL_POINTERS_PREAMBLE(m)
#define X(type, name, rows, cols)                                                   \
  if (bad.empty() && (std::is_same_v<type, mjtNum> || std::is_same_v<type, float>)) \
    bad = check(#name, m->name, static_cast<long>(m->rows) * (cols));
  MJMODEL_POINTERS
#undef X
      (void)
      nuser_body,
      (void)nuser_jnt, (void)nuser_geom, (void)nuser_site, (void)nuser_cam;
  (void)nuser_tendon, (void)nuser_actuator, (void)nuser_sensor, (void)nq, (void)nv, (void)na;
  (void)nu, (void)nmocap;
  const mjOption& o = m->opt;
  const mjtNum options[] = {
      o.timestep,      o.apirate,     o.impratio,    o.tolerance,   o.noslip_tolerance,
      o.mpr_tolerance, o.gravity[0],  o.gravity[1],  o.gravity[2],  o.wind[0],
      o.wind[1],       o.wind[2],     o.magnetic[0], o.magnetic[1], o.magnetic[2],
      o.density,       o.viscosity,   o.o_margin,    o.o_solref[0], o.o_solref[1],
      o.o_solimp[0],   o.o_solimp[1], o.o_solimp[2], o.o_solimp[3], o.o_solimp[4]};
  if (bad.empty()) bad = check("option", options, std::size(options));
  const mjStatistic& st = m->stat;
  const mjtNum statistics[] = {st.meaninertia, st.meanmass,  st.meansize, st.extent,
                               st.center[0],   st.center[1], st.center[2]};
  if (bad.empty()) bad = check("statistic", statistics, std::size(statistics));
  const mjVisual& v = m->vis;
  const float global[] = {v.global.fovy,      v.global.ipd,       v.global.azimuth,
                          v.global.elevation, v.global.linewidth, v.global.glow};
  if (bad.empty()) bad = check("visual.global", global, std::size(global));
  // visual.map, visual.scale and visual.rgba hold floats only.
  if (bad.empty()) {
    bad = check("visual.map", reinterpret_cast<const float*>(&v.map), sizeof v.map / sizeof(float));
  }
  if (bad.empty()) {
    bad = check("visual.scale", reinterpret_cast<const float*>(&v.scale),
                sizeof v.scale / sizeof(float));
  }
  if (bad.empty()) {
    bad = check("visual.rgba", reinterpret_cast<const float*>(&v.rgba),
                sizeof v.rgba / sizeof(float));
  }
  return bad;
}

ModelPtr checked(mjModel* m, const std::string& label) {
  ModelPtr model(m);
  if (const std::string bad = non_finite_field(m); !bad.empty()) {
    throw InputError(label, "",
                     "the compiled model holds NaN or infinity in " + bad +
                         " (a number in the file is nan, inf or out of range)");
  }
  return model;
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
  return checked(m, label);
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
  return checked(m, path);
}

ModelPtr copy_model(const mjModel* m) { return ModelPtr(mj_copyModel(nullptr, m)); }

DataPtr make_data(const mjModel* m) { return DataPtr(mj_makeData(m)); }

}  // namespace taskmatrix::mujoco
