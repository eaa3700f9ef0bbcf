// Exclusive use of a run directory. A run writes only into a directory that is new, empty, or
// one of its own (marked by the file .taskmatrix-run, or, for directories written before the
// marker existed, holding a provenance.json with a scenario_hash): it refuses any other
// directory, so a user's folder is never overwritten. While it runs it holds an exclusive lock
// (flock) on the marker, which names the holder's PID and command line: a second run into the
// same directory fails at once, naming them. Replacing the results of an earlier run removes
// only the files runs write (trials.jsonl, summary.json, summary.md, ompl.log, planners.md,
// planners.html, provenance.json, trajectories/*.traj.gz); anything else in it stays.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace taskmatrix::harness {

class RunDirectoryLock {
 public:
  // Creates `dir` when missing and locks it. Throws core::InputError naming `option` (the
  // command-line option that named the directory) when it is not a directory, when it holds
  // files but is not a run directory, or when another process holds it.
  RunDirectoryLock(const std::filesystem::path& dir, const std::vector<std::string>& command_line,
                   const std::string& option = "--out");
  ~RunDirectoryLock();
  RunDirectoryLock(const RunDirectoryLock&) = delete;
  RunDirectoryLock& operator=(const RunDirectoryLock&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  // Removes the files an earlier run wrote (see above), nothing else.
  void remove_previous_results() const;

 private:
  std::filesystem::path dir_;
  int fd_ = -1;
};

// The marker's name inside a run directory.
inline constexpr const char* kRunDirectoryMarker = ".taskmatrix-run";

}  // namespace taskmatrix::harness
