#include "harness/run/worker_pool.h"
#include "taskmatrix/core/motion_planning.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace taskmatrix::harness {

namespace {

using Clock = std::chrono::steady_clock;

int g_result_fd = -1;  // in a worker: where its payload goes

void write_all(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return;
    }
    data += n;
    size -= static_cast<size_t>(n);
  }
}

[[noreturn]] void run_child(int fd, size_t i, pid_t supervisor, const WorkerPoolOptions& options,
                            const std::function<std::string(size_t)>& work) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != supervisor) _exit(72);  // the supervisor died before prctl took effect
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGPIPE, SIG_DFL);
  g_result_fd = fd;
  std::string payload;
  int code = 0;
  try {
    if (options.in_worker) options.in_worker();
    payload = work(i);
  } catch (const std::exception& e) {
    payload = std::string("!crash exception: ") + e.what();
    code = 71;
  } catch (...) {
    payload = "!crash unknown exception";
    code = 71;
  }
  std::fflush(nullptr);
  write_all(fd, payload.data(), payload.size());
  close(fd);
  _exit(code);
}

struct Running {
  size_t task;
  pid_t pid;
  int fd;
  Clock::time_point start, deadline;
  std::string payload;
  bool eof = false;
  bool timed_out = false;
};

// Reads what is in the pipe now without waiting; true at end of file.
bool drain(Running& r) {
  const int flags = fcntl(r.fd, F_GETFL);
  fcntl(r.fd, F_SETFL, flags | O_NONBLOCK);
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = read(r.fd, buf, sizeof buf);
    if (n > 0) {
      r.payload.append(buf, static_cast<size_t>(n));
      continue;
    }
    fcntl(r.fd, F_SETFL, flags);
    return n == 0;
  }
}

// Kills and reaps the running workers when the supervisor leaves by an exception.
struct KillOnUnwind {
  std::vector<Running>& running;
  ~KillOnUnwind() {
    for (Running& r : running) {
      kill(r.pid, SIGKILL);
      close(r.fd);
      waitpid(r.pid, nullptr, 0);
    }
  }
};

std::string signal_text(int sig) {
  const char* name = strsignal(sig);
  return "the worker died of signal " + std::to_string(sig) + " (" + (name ? name : "?") + ")";
}

}  // namespace

void crash_worker(const char* reason) {
  // Outside a worker (no result pipe), the reason goes to stderr.
  const std::string payload =
      g_result_fd >= 0 ? std::string("!crash ") + reason : std::string(reason) + "\n";
  write_all(g_result_fd >= 0 ? g_result_fd : 2, payload.data(), payload.size());
  _exit(70);
}

size_t run_in_workers(size_t count, const WorkerPoolOptions& options,
                      const std::function<std::string(size_t)>& work,
                      const std::function<double(size_t)>& wall_limit_s,
                      const std::function<void(size_t, const WorkerOutcome&)>& on_done) {
  if (options.jobs < 1) throw std::invalid_argument("jobs must be 1 or more");
  std::vector<Running> running;
  const KillOnUnwind guard{running};
  const pid_t supervisor = getpid();
  size_t next = 0, reported = 0;
  auto stopping = [&] { return options.stop && *options.stop != 0; };
  std::fflush(nullptr);  // nothing buffered is written twice by a child

  while ((next < count && !stopping()) || !running.empty()) {
    if (stopping()) {
      for (Running& r : running) {
        kill(r.pid, SIGKILL);
        close(r.fd);
        waitpid(r.pid, nullptr, 0);
      }
      running.clear();
      break;
    }
    while (next < count && static_cast<int>(running.size()) < options.jobs) {
      int fds[2];
      if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
      const Clock::time_point start = Clock::now();
      const pid_t pid = fork();
      if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
      }
      if (pid == 0) {
        close(fds[0]);
        run_child(fds[1], next, supervisor, options, work);
      }
      close(fds[1]);
      const auto limit = std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(wall_limit_s(next)));
      running.push_back({next, pid, fds[0], start, start + limit, "", false, false});
      ++next;
    }
    // Wait for output, an end, or the nearest deadline.
    std::vector<pollfd> pfds;
    Clock::time_point nearest = Clock::time_point::max();
    for (const Running& r : running) {
      pfds.push_back({r.fd, POLLIN, 0});
      nearest = std::min(nearest, r.deadline);
    }
    const auto wait_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(nearest - Clock::now()).count();
    const int timeout =
        static_cast<int>(std::max<long long>(0, std::min<long long>(wait_ms + 1, 200)));
    const int ready = poll(pfds.data(), pfds.size(), timeout);
    if (ready < 0 && errno != EINTR) throw std::runtime_error("poll failed");
    for (size_t k = 0; k < running.size(); ++k) {
      Running& r = running[k];
      if (ready > 0 && (pfds[k].revents & (POLLIN | POLLHUP | POLLERR))) {
        char buf[1 << 16];
        const ssize_t n = read(r.fd, buf, sizeof buf);
        if (n > 0) r.payload.append(buf, static_cast<size_t>(n));
        if (n == 0) r.eof = true;
      }
      if (!r.eof && Clock::now() >= r.deadline) {
        // A worker that finished just now is not a timeout.
        if (!drain(r)) {
          kill(r.pid, SIGKILL);
          r.timed_out = true;
        }
        r.eof = true;
      }
    }
    for (size_t k = 0; k < running.size();) {
      Running& r = running[k];
      if (!r.eof) {
        ++k;
        continue;
      }
      close(r.fd);
      int status = 0;
      rusage usage{};
      while (wait4(r.pid, &status, 0, &usage) < 0 && errno == EINTR) {
      }
      WorkerOutcome out;
      out.wall_s = core::seconds_since(r.start);
      out.peak_memory_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
      out.cpu_s = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                  1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
      if (r.timed_out) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "no result within the wall-clock limit of %g s; killed",
                      wall_limit_s(r.task));
        out.failure = core::Failure(core::FailureCode::kTimeout, buf);
      } else if (r.payload.rfind("!crash ", 0) == 0) {
        out.failure = core::Failure(core::FailureCode::kCrash, r.payload.substr(7));
      } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && !r.payload.empty()) {
        out.has_result = true;
        out.payload = std::move(r.payload);
      } else if (WIFSIGNALED(status)) {
        out.failure = core::Failure(core::FailureCode::kCrash, signal_text(WTERMSIG(status)));
      } else {
        out.failure = core::Failure(
            core::FailureCode::kCrash,
            "the worker exited with status " +
                std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + " without a result");
      }
      const size_t task = r.task;
      running.erase(running.begin() + static_cast<long>(k));
      if (stopping()) continue;  // an interrupted run reports nothing more
      on_done(task, out);
      ++reported;
    }
  }
  return reported;
}

}  // namespace taskmatrix::harness
