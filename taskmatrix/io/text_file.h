// Reads a whole text file; throws core::InputError naming the file when it cannot.
#pragma once

#include <filesystem>
#include <string>

namespace taskmatrix::io {

std::string read_text_file(const std::filesystem::path& file);

}  // namespace taskmatrix::io
