#include "harness/results/run_directory.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

namespace fs = std::filesystem;

const char* const kResultFiles[] = {"trials.jsonl", "summary.json",  "summary.md",     "ompl.log",
                                    "planners.md",  "planners.html", "provenance.json"};

// A run directory written before the marker existed: its provenance names the scenario hash.
bool is_unmarked_run_directory(const fs::path& dir) {
  std::ifstream in(dir / "provenance.json");
  if (!in) return false;
  const nlohmann::json p = nlohmann::json::parse(in, nullptr, false);
  return p.is_object() && p.contains("scenario_hash") && p["scenario_hash"].is_string();
}

std::string holder_text(const std::vector<std::string>& command_line) {
  std::string command;
  for (const std::string& a : command_line) command += (command.empty() ? "" : " ") + a;
  for (char& c : command) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (command.size() > 400) command = command.substr(0, 397) + "...";
  return "taskmatrix run directory\npid " + std::to_string(getpid()) + "\ncommand " + command +
         "\n";
}

// "PID 123 (taskmatrix run ...)" from the marker's text.
std::string describe_holder(int fd) {
  char buf[1024];
  const ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return "a process that has not yet named itself";
  const std::string text(buf, static_cast<size_t>(n));
  auto value = [&](const std::string& key) {
    const size_t at = text.find("\n" + key + " ");
    if (at == std::string::npos) return std::string("?");
    const size_t from = at + key.size() + 2;
    return text.substr(from, text.find('\n', from) - from);
  };
  return "PID " + value("pid") + ": " + value("command");
}

}  // namespace

RunDirectoryLock::RunDirectoryLock(const fs::path& dir,
                                   const std::vector<std::string>& command_line,
                                   const std::string& option)
    : dir_(dir) {
  const std::string name = dir.string();
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw core::InputError(name, option, "exists and is not a directory");
  }
  fs::create_directories(dir, ec);
  if (ec) throw core::InputError(name, option, "cannot create the directory: " + ec.message());
  const fs::path marker = dir / kRunDirectoryMarker;
  const bool ours = fs::exists(marker, ec) || is_unmarked_run_directory(dir);
  if (!ours && !fs::is_empty(dir, ec)) {
    throw core::InputError(name, option,
                           "holds files but is not a run directory (no " +
                               std::string(kRunDirectoryMarker) +
                               "); a run writes only into a new, empty or earlier run directory: "
                               "choose another");
  }
  fd_ = open(marker.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw core::InputError(
        marker.string(), option,
        std::string("cannot create the run directory's marker: ") + std::strerror(errno));
  }
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = describe_holder(fd_);
    close(fd_);
    fd_ = -1;
    throw core::InputError(name, option,
                           "is in use by another run (" + holder +
                               "); wait for it to end or choose another directory");
  }
  const std::string text = holder_text(command_line);
  if (ftruncate(fd_, 0) != 0 ||
      pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    close(fd_);
    fd_ = -1;
    throw core::InputError(
        marker.string(), option,
        std::string("cannot write the run directory's marker: ") + std::strerror(errno));
  }
}

RunDirectoryLock::~RunDirectoryLock() {
  if (fd_ >= 0) close(fd_);
}

void RunDirectoryLock::remove_previous_results() const {
  for (const char* name : kResultFiles) {
    fs::remove(dir_ / name);
    fs::remove(dir_ / (std::string(name) + ".tmp"));
  }
  std::error_code ec;
  if (!fs::is_directory(dir_ / "trajectories", ec)) return;
  for (const auto& entry : fs::directory_iterator(dir_ / "trajectories")) {
    const std::string file = entry.path().filename().string();
    auto ends_with = [&](const std::string& suffix) {
      return file.size() > suffix.size() &&
             file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    if (entry.is_regular_file() && (ends_with(".traj.gz") || ends_with(".traj.gz.tmp"))) {
      fs::remove(entry.path());
    }
  }
}

}  // namespace taskmatrix::harness
