#include "taskmatrix/io/text_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::io {

std::string read_text_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw core::InputError(file.string(), "", "cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void write_file_checked(const std::filesystem::path& file, std::string_view data) {
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(file.string() + ": cannot write: " + std::strerror(errno));
  size_t done = 0;
  int error = 0;
  while (done < data.size() && error == 0) {
    const ssize_t n = write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
    } else {
      done += static_cast<size_t>(n);
    }
  }
  // A full disk may show only when the data is synced or the file closed. fsync fails with
  // EINVAL on what cannot be synced (a pipe, /dev/null): that is no write error.
  if (error == 0 && fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    std::error_code ignored;
    if (std::filesystem::is_regular_file(file, ignored)) std::filesystem::remove(file, ignored);
    throw std::runtime_error(file.string() + ": cannot write: " + std::strerror(error));
  }
}

void write_file_atomically(const std::filesystem::path& file, std::string_view data) {
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec)) {
    write_file_checked(file, data);  // a device or pipe (/dev/stdout) cannot be replaced
    return;
  }
  const std::filesystem::path tmp = file.string() + ".tmp";
  write_file_checked(tmp, data);
  std::filesystem::rename(tmp, file);
}

}  // namespace taskmatrix::io
