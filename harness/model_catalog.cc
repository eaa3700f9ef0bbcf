#include "harness/model_catalog.h"

#include <algorithm>
#include <cstdlib>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {
namespace {

std::vector<std::string> entries_with(const std::filesystem::path& dir, const char* file) {
  std::vector<std::string> names;
  if (!std::filesystem::is_directory(dir)) return names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_directory() && std::filesystem::is_regular_file(entry.path() / file)) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path lookup(const std::vector<std::string>& known,
                             const std::filesystem::path& dir, const std::string& kind,
                             const std::string& name) {
  if (std::find(known.begin(), known.end(), name) != known.end()) return dir / name;
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  throw core::InputError(dir.string(), "",
                         "unknown " + kind + " '" + name + "' (known: " + list + ")");
}

}  // namespace

ModelCatalog::ModelCatalog(std::filesystem::path root) : root_(std::move(root)) {}

ModelCatalog ModelCatalog::from_environment() {
  const char* env = std::getenv("TASKMATRIX_ROOT");
  return ModelCatalog(env && *env ? env : TASKMATRIX_DEFAULT_ROOT);
}

std::vector<std::string> ModelCatalog::robots() const {
  return entries_with(root_ / "models" / "robots", "profile.yaml");
}

std::vector<std::string> ModelCatalog::environments() const {
  return entries_with(root_ / "models" / "environments", "environment.yaml");
}

std::filesystem::path ModelCatalog::robot_dir(const std::string& name) const {
  return lookup(robots(), root_ / "models" / "robots", "robot", name);
}

std::filesystem::path ModelCatalog::environment_dir(const std::string& name) const {
  return lookup(environments(), root_ / "models" / "environments", "environment", name);
}

}  // namespace taskmatrix::harness
