// The planners a run can use: the built-in ones (OMPL's, taskmatrix/ompl; the project's,
// taskmatrix/planners) and planner plugins, shared libraries loaded by path from a scenario's
// `planners:` list ({plugin: path/to/libmyplanner.so, name: MyPlanner, params: {...}}), all in
// the process's registry (core::planner_registry()).
//
// A plugin is built against taskmatrix/core/motion_planning.h and defines its entry point with
// TASKMATRIX_PLANNER_PLUGIN (examples/planner_plugin/). Loading it checks its API version,
// then lets it register its planners; a library is loaded once per process and stays loaded.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace taskmatrix::harness {

// Registers the built-in planners once per process (later calls do nothing).
void register_builtin_planners();

// Loads the plugin at `path` (once; later calls with the same file return what the first did)
// and returns the planner names it registered. Throws std::runtime_error with a one-line
// reason: no such file, not a shared library (dlopen's message), a missing entry point, an API
// version other than this build's, or a registration the registry refuses (a taken name).
std::vector<std::string> load_planner_plugin(const std::filesystem::path& path);

}  // namespace taskmatrix::harness
