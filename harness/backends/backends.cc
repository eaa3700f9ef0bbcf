#include "harness/backends/backends.h"

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/mujoco_backend.h"

namespace taskmatrix::harness {

std::vector<std::string> backend_names() { return {"mujoco"}; }

const core::Backend& backend(const std::string& name) {
  static const mujoco::MujocoBackend mujoco_backend;
  if (name == mujoco_backend.name()) return mujoco_backend;
  std::string known;
  for (const std::string& n : backend_names()) known += (known.empty() ? "" : ", ") + n;
  throw core::InputError("backend", "", "unknown backend '" + name + "' (known: " + known + ")");
}

}  // namespace taskmatrix::harness
