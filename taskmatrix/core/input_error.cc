#include "taskmatrix/core/input_error.h"

#include <utility>

namespace taskmatrix::core {
namespace {

std::string format(const std::string& file, const std::string& key, const std::string& message,
                   int line) {
  std::string out;
  out.append(file.empty() ? std::string("<input>") : file);
  if (line > 0) out.append(":").append(std::to_string(line));
  out.append(": ");
  if (!key.empty()) out.append(key).append(": ");
  out.append(message);
  // One line, always: multi-line messages from libraries are folded.
  for (char& c : out) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return out;
}

}  // namespace

InputError::InputError(std::string file, std::string key, const std::string& message, int line)
    : std::runtime_error(format(file, key, message, line)),
      file_(std::move(file)),
      key_(std::move(key)),
      message_(message),
      line_(line) {}

}  // namespace taskmatrix::core
