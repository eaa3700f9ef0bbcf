// RAII owners for MuJoCo handles and the one place where MJCF text is compiled, with
// MuJoCo's error buffer and warnings turned into core::InputError.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include <mujoco/mujoco.h>

namespace taskmatrix::mujoco {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Compiles MJCF text held in memory. `label` names the input in errors (for a composed scene,
// the robot and environment files). Throws core::InputError with MuJoCo's message.
ModelPtr compile_mjcf_text(const std::string& xml, const std::string& label);

// Compiles a file (MJCF or URDF) from disk. Throws core::InputError naming `path`.
ModelPtr compile_file(const std::string& path);

// MuJoCo's XML loader keeps process-global state (the last loaded model, which
// mj_saveLastXML writes): every load and save holds this lock.
std::recursive_mutex& mujoco_loader_mutex();

ModelPtr copy_model(const mjModel* m);
DataPtr make_data(const mjModel* m);

// Replaces MuJoCo's default error handler (print and exit) with one that prints a single
// line naming MuJoCo and exits with status 3, and prints each warning as one line on
// stderr.
// Idempotent.
void install_mujoco_error_handlers();

}  // namespace taskmatrix::mujoco
