#include "harness/scenario/planner_plugins.h"

#include <dlfcn.h>

#include <map>
#include <mutex>
#include <stdexcept>

#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/ompl/ompl_planners.h"
#include "taskmatrix/planners/line_connect.h"

namespace taskmatrix::harness {

namespace {

// Adds to the registry and remembers the names added.
class RecordingRegistrar : public core::PlannerRegistrar {
 public:
  void add(core::PlannerType type) override {
    std::string name = type.name;
    core::planner_registry().add(std::move(type));
    names.push_back(std::move(name));
  }
  std::vector<std::string> names;
};

}  // namespace

void register_builtin_planners() {
  static std::once_flag once;
  std::call_once(once, [] {
    ompl_planners::register_planners(core::planner_registry());
    planners::register_planners(core::planner_registry());
  });
}

std::vector<std::string> load_planner_plugin(const std::filesystem::path& path) {
  static std::mutex mutex;
  static std::map<std::filesystem::path, std::vector<std::string>> loaded;
  register_builtin_planners();
  std::lock_guard<std::mutex> lock(mutex);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw std::runtime_error("planner plugin " + path.string() + " does not exist");
  }
  const std::filesystem::path file = std::filesystem::canonical(path);
  if (const auto it = loaded.find(file); it != loaded.end()) return it->second;
  // RTLD_LOCAL: two plugins may define the same internal symbols. Never closed: the planner
  // types registered point into it.
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    throw std::runtime_error("cannot load planner plugin " + path.string() + ": " +
                             (why ? why : "unknown reason"));
  }
  using ApiFunction = int (*)();
  using RegisterFunction = void (*)(core::PlannerRegistrar&);
  auto api = reinterpret_cast<ApiFunction>(dlsym(handle, "taskmatrix_planner_plugin_api"));
  auto add = reinterpret_cast<RegisterFunction>(dlsym(handle, "taskmatrix_register_planners"));
  if (api == nullptr || add == nullptr) {
    throw std::runtime_error(
        "planner plugin " + path.string() + " does not define " +
        (api == nullptr ? "taskmatrix_planner_plugin_api" : "taskmatrix_register_planners") +
        " (TASKMATRIX_PLANNER_PLUGIN in taskmatrix/core/motion_planning.h)");
  }
  if (const int version = api(); version != core::kPlannerPluginApi) {
    throw std::runtime_error("planner plugin " + path.string() + " was built for planner API " +
                             std::to_string(version) + "; this build has " +
                             std::to_string(core::kPlannerPluginApi) + ": rebuild it");
  }
  RecordingRegistrar registrar;
  try {
    add(registrar);
  } catch (const std::exception& e) {
    throw std::runtime_error("planner plugin " + path.string() + ": " + e.what());
  }
  if (registrar.names.empty()) {
    throw std::runtime_error("planner plugin " + path.string() + " registered no planner");
  }
  loaded[file] = registrar.names;
  return registrar.names;
}

}  // namespace taskmatrix::harness
