// Reads a whole text file; throws core::InputError naming the file when it cannot. Writes a
// file so that a failure (a full disk, a read-only folder) is an error, never a short file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace taskmatrix::io {

std::string read_text_file(const std::filesystem::path& file);

// Writes `data` to `file` (created or truncated), checking every write, the sync and the close;
// on failure removes `file` and throws std::runtime_error naming it and the system's reason.
void write_file_checked(const std::filesystem::path& file, std::string_view data);

// write_file_checked to "<file>.tmp", then a rename onto `file`: readers see the old file or
// the whole new one. A `file` that exists but is no regular file (a pipe) is written directly.
void write_file_atomically(const std::filesystem::path& file, std::string_view data);

}  // namespace taskmatrix::io
