// The backends the harness can run trials on, by name (core/backend.h is the interface). The
// harness reaches a simulator only through the Backend these return; adding a backend is one
// class implementing core/backend.h and one line in backends.cc.
#pragma once

#include <string>
#include <vector>

#include "taskmatrix/core/backend.h"

namespace taskmatrix::harness {

// "mujoco".
std::vector<std::string> backend_names();
// The backend named `name`. Throws core::InputError("backend") naming the known ones for an
// unknown name.
const core::Backend& backend(const std::string& name = "mujoco");

}  // namespace taskmatrix::harness
