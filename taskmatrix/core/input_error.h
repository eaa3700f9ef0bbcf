// One error type for every bad input (YAML, MJCF, URDF, profile, CLI argument): it names the
// file and, where known, the line and key, so that the CLI can print a single clear line.
#pragma once

#include <stdexcept>
#include <string>

namespace taskmatrix::core {

class InputError : public std::runtime_error {
 public:
  // `key` is a dotted path such as "chains.left_arm.joints[2]"; empty when unknown.
  // `line` is 1-based; 0 when unknown.
  InputError(std::string file, std::string key, const std::string& message, int line = 0);

  const std::string& file() const { return file_; }
  const std::string& key() const { return key_; }
  int line() const { return line_; }
  // The message without the "file:line: key:" prefix.
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  std::string key_;
  std::string message_;
  int line_;
};

}  // namespace taskmatrix::core
