#include "harness/scenario/model_catalog.h"

#include <algorithm>
#include <cstdlib>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/utf8.h"

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
  if (std::find(known.begin(), known.end(), name) != known.end()) {
    if (const std::string bad = unsafe_name_reason(kind, name); !bad.empty()) {
      throw core::InputError((dir / name).string(), "", bad + "; rename the directory");
    }
    return dir / name;
  }
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  throw core::InputError(dir.string(), "",
                         "unknown " + kind + " '" + name + "' (known: " + list + ")");
}

}  // namespace

bool is_safe_name(const std::string& name) {
  return !name.empty() && name.size() <= kMaxNameLength &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                  c == '_' || c == '-';
         });
}

std::string unsafe_name_reason(const std::string& what, const std::string& name) {
  if (is_safe_name(name)) return "";
  std::string shown = core::valid_utf8(name.substr(0, 80));
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 0x20) c = '?';
  }
  return what + " name '" + shown + (name.size() > 80 ? "...'" : "'") +
         " must be 1 to 64 of A-Z a-z 0-9 _ - (it becomes part of trial ids and file names)";
}

ModelCatalog::ModelCatalog(std::filesystem::path root) : root_(std::move(root)) {}

ModelCatalog ModelCatalog::from_environment() {
  const char* env = std::getenv("TASKMATRIX_ROOT");
  return ModelCatalog(env && *env ? std::filesystem::path(env) : built_in_root());
}

std::filesystem::path ModelCatalog::built_in_root() { return TASKMATRIX_DEFAULT_ROOT; }

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
