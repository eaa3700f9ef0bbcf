// Finds robots and environments by name under the project root (models/robots/<name>/,
// models/environments/<name>/). The root is $TASKMATRIX_ROOT, else the source tree the
// binary was built from.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace taskmatrix::harness {

class ModelCatalog {
 public:
  explicit ModelCatalog(std::filesystem::path root);
  static ModelCatalog from_environment();

  const std::filesystem::path& root() const { return root_; }
  std::vector<std::string> robots() const;        // sorted names
  std::vector<std::string> environments() const;  // sorted names
  // Throw core::InputError listing the known names when `name` is unknown.
  std::filesystem::path robot_dir(const std::string& name) const;
  std::filesystem::path environment_dir(const std::string& name) const;

 private:
  std::filesystem::path root_;
};

}  // namespace taskmatrix::harness
