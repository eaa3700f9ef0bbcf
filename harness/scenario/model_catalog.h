// Finds robots and environments by name under the project root (models/robots/<name>/,
// models/environments/<name>/). The root is $TASKMATRIX_ROOT, else the source tree the
// binary was built from.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace taskmatrix::harness {

// Names that become parts of trial ids, file and directory names (robots, environments,
// scenarios, suites, planner labels): 1 to 64 of A-Z a-z 0-9 _ -.
inline constexpr std::size_t kMaxNameLength = 64;
bool is_safe_name(const std::string& name);
// "" if `name` is safe, else what is wrong (for an error naming the file and key).
std::string unsafe_name_reason(const std::string& what, const std::string& name);

class ModelCatalog {
 public:
  explicit ModelCatalog(std::filesystem::path root);
  static ModelCatalog from_environment();
  // The source tree the program was built from (its models/ and scenarios/).
  static std::filesystem::path built_in_root();

  const std::filesystem::path& root() const { return root_; }
  std::vector<std::string> robots() const;        // sorted names
  std::vector<std::string> environments() const;  // sorted names
  // Throw core::InputError listing the known names when `name` is unknown, and naming the
  // directory when its name is not safe (is_safe_name).
  std::filesystem::path robot_dir(const std::string& name) const;
  std::filesystem::path environment_dir(const std::string& name) const;

 private:
  std::filesystem::path root_;
};

}  // namespace taskmatrix::harness
