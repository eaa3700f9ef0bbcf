#include "taskmatrix/io/text_file.h"

#include <fstream>
#include <sstream>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::io {

std::string read_text_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw core::InputError(file.string(), "", "cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace taskmatrix::io
