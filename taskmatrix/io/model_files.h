// Reading the YAML files that describe models: robot profiles and environment specs.
// Every error names the file, line and key.
#pragma once

#include <filesystem>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/robot_profile.h"

namespace taskmatrix::io {

// Reads models/robots/<name>/profile.yaml and checks its structure (not yet the model).
core::RobotProfile load_robot_profile(const std::filesystem::path& profile_file);

// Reads models/environments/<name>/environment.yaml.
core::EnvironmentSpec load_environment_spec(const std::filesystem::path& spec_file);

}  // namespace taskmatrix::io
