// Trials in worker processes: each task runs in a child forked from the supervisor (which has
// loaded the models, so a worker starts in well under a millisecond of work and every worker
// starts from the same state: results do not depend on how many run at once or in which
// order). At most `jobs` run at a time; each has a wall-clock limit after which it is killed
// (SIGKILL). A worker that dies (signal, exit without a result, crash_worker) or is killed is
// reported with status "crash" or "timeout" and the others go on.
//
// Workers ignore SIGINT (the supervisor decides what an interrupt means) and die with the
// supervisor (PR_SET_PDEATHSIG), so a killed run leaves no orphans.
#pragma once

#include <atomic>
#include <csignal>
#include <functional>
#include <string>

#include "taskmatrix/core/failure.h"

namespace taskmatrix::harness {

struct WorkerOutcome {
  bool has_result = false;  // the worker wrote its payload and exited 0
  std::string payload;
  core::Failure failure;      // when !has_result: kCrash or kTimeout, and what happened
  double wall_s = 0;          // fork to reaped
  double peak_memory_mb = 0;  // the worker's maximum resident set (getrusage of the child)
  double cpu_s = 0;           // the worker's user + system CPU time (getrusage of the child)
};

struct WorkerPoolOptions {
  int jobs = 1;
  // Checked between events; when it becomes non-zero, no new worker starts, running workers
  // are killed and their outcomes are not reported.
  const volatile std::sig_atomic_t* stop = nullptr;
  // Runs first in each worker (a backend routing its fatal errors to crash_worker).
  std::function<void()> in_worker;
};

// In a worker: reports `reason` as its crash ("crash" status, the reason as given) and ends
// it. For hooks that cannot return, as a simulator's fatal-error handler.
[[noreturn]] void crash_worker(const char* reason);

// Runs work(i) for i in [0, count) in workers. `work` runs in the child and returns the
// payload; an exception there is reported as a crash with its message. `wall_limit_s(i)` is
// task i's limit. on_done(i, outcome) runs in the supervisor as each task ends, in the order
// they end. Returns the number of tasks reported (count unless stopped).
size_t run_in_workers(size_t count, const WorkerPoolOptions& options,
                      const std::function<std::string(size_t)>& work,
                      const std::function<double(size_t)>& wall_limit_s,
                      const std::function<void(size_t, const WorkerOutcome&)>& on_done);

}  // namespace taskmatrix::harness
