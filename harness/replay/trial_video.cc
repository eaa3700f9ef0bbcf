#include "harness/replay/trial_video.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "harness/replay/replay.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/png.h"

extern char** environ;

namespace taskmatrix::harness {

namespace {

// "lookat:X,Y,Z[,D[,AZ[,EL]]]" into `view`.
void parse_lookat(const std::string& camera, core::Camera& view) {
  std::vector<double> v;
  std::stringstream in(camera.substr(7));
  for (std::string item; std::getline(in, item, ',');) {
    size_t used = 0;
    double x = NAN;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(x)) {
      throw core::InputError("--camera", "",
                             "'" + camera + "': '" + item + "' is not a number (expected " +
                                 "lookat:X,Y,Z[,DISTANCE[,AZIMUTH[,ELEVATION]]])");
    }
    v.push_back(x);
  }
  if (v.size() < 3 || v.size() > 6) {
    throw core::InputError("--camera", "",
                           "'" + camera +
                               "' needs 3 to 6 numbers: lookat:X,Y,Z[,DISTANCE[,AZIMUTH[,"
                               "ELEVATION]]] (metres and degrees)");
  }
  if (v.size() > 3 && !(v[3] > 0)) {
    throw core::InputError("--camera", "", "'" + camera + "': the distance must be positive");
  }
  if (v.size() > 5 && std::fabs(v[5]) > 90) {
    throw core::InputError("--camera", "",
                           "'" + camera + "': the elevation must be within -90..90 degrees");
  }
  view.name.clear();
  view.lookat = Eigen::Vector3d(v[0], v[1], v[2]);
  view.distance = v.size() > 3 ? v[3] : 1.5;
  view.azimuth = v.size() > 4 ? v[4] : 210;
  view.elevation = v.size() > 5 ? v[5] : -25;
}

}  // namespace

std::string lookat_camera_text(const core::Camera& view) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "lookat:%.3f,%.3f,%.3f,%.2f,%.0f,%.0f", view.lookat[0],
                view.lookat[1], view.lookat[2], view.distance, view.azimuth, view.elevation);
  return buf;
}

core::Camera camera_view(const core::SceneView& scene, std::string& camera) {
  core::Camera view;
  const std::vector<std::string> cameras = scene.cameras();
  if (camera.empty()) camera = cameras.empty() ? "free" : cameras[0];
  if (camera.rfind("lookat:", 0) == 0) {
    parse_lookat(camera, view);
  } else if (camera == "head") {
    view.name = camera;
  } else if (camera != "free") {
    if (std::find(cameras.begin(), cameras.end(), camera) == cameras.end()) {
      std::string known = "head, free, lookat:X,Y,Z[,D[,AZ[,EL]]]";
      for (const std::string& c : cameras) known += ", " + c;
      throw core::InputError("--camera", "",
                             "unknown camera '" + camera + "' (known: " + known + ")");
    }
    view.name = camera;
  }
  return view;
}

namespace {

constexpr double kMaxVideoFrames = 90000;

std::unique_ptr<Replay> load_replay(const ModelCatalog& catalog,
                                    const std::string& run_dir_and_trial) {
  const std::filesystem::path file = trajectory_of(run_dir_and_trial);
  auto replay = std::make_unique<Replay>(catalog, read_trajectory_file(file));
  if (replay->frames() == 0) throw core::InputError(file.string(), "frames", "no frames");
  return replay;
}

// The image size against the model's offscreen buffer (and H.264's 4:2:0 subsampling).
void check_size(const core::SceneView& scene, const FrameOptions& options, bool even) {
  const auto check = [even](const char* argument, int value, int limit) {
    if (value < 1 || value > limit) {
      throw core::InputError(argument, "",
                             std::to_string(value) + " is outside 1.." + std::to_string(limit) +
                                 " (the model's offscreen buffer)");
    }
    if (even && value % 2 != 0) {
      throw core::InputError(
          argument, "",
          std::to_string(value) + " is odd: H.264 video (yuv420p) needs an even width and height");
    }
  };
  check("--width", options.width, scene.max_width());
  check("--height", options.height, scene.max_height());
}

// An executable `name` in a folder of $PATH (as execvp would find it); empty if none.
std::filesystem::path find_on_path(const std::string& name) {
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/bin:/bin";
  for (size_t start = 0;;) {
    const size_t end = path.find(':', start);
    std::string dir = path.substr(start, end == std::string::npos ? end : end - start);
    if (dir.empty()) dir = ".";
    const std::filesystem::path candidate = std::filesystem::path(dir) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    if (end == std::string::npos) return {};
    start = end + 1;
  }
}

// A descriptor above the standard three (so that dup2 onto 0..2 in the child cannot clobber
// another of ours when the parent runs with a standard stream closed), close-on-exec.
int above_std(int fd) {
  if (fd < 0 || fd > 2) return fd;
  const int moved = fcntl(fd, F_DUPFD_CLOEXEC, 3);
  close(fd);
  return moved;
}

// SIGPIPE blocked in this thread while it lives: a write to a pipe whose reader is gone
// fails with EPIPE instead of killing the process. A SIGPIPE raised meanwhile is consumed.
class SigpipeBlocked {
 public:
  SigpipeBlocked() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
  }
  ~SigpipeBlocked() {
    sigset_t pending;
    sigemptyset(&pending);
    if (!sigismember(&old_, SIGPIPE) && sigpending(&pending) == 0 &&
        sigismember(&pending, SIGPIPE)) {
      const timespec zero{};
      sigtimedwait(&pipe_, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlocked(const SigpipeBlocked&) = delete;
  SigpipeBlocked& operator=(const SigpipeBlocked&) = delete;

 private:
  sigset_t pipe_, old_;
};

// ffmpeg reading raw frames on its stdin, its stderr kept in an unlinked temporary file.
// Destroying a running encoder kills and reaps it.
class Encoder {
 public:
  Encoder(const std::filesystem::path& program, const std::vector<std::string>& args) {
    const std::string tmp = (std::filesystem::temp_directory_path() / "taskmatrix_ffmpeg_XXXXXX");
    std::vector<char> name(tmp.begin(), tmp.end());
    name.push_back('\0');
    stderr_fd_ = above_std(mkostemp(name.data(), O_CLOEXEC));
    if (stderr_fd_ < 0) throw std::runtime_error("cannot create a temporary file for ffmpeg");
    unlink(name.data());
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot make a pipe for ffmpeg");
    const int read_end = above_std(fds[0]);
    stdin_fd_ = above_std(fds[1]);
    // A deeper pipe lets rendering run ahead of encoding (best effort).
    fcntl(stdin_fd_, F_SETPIPE_SZ, 1 << 20);
    const int null_fd = above_std(open("/dev/null", O_WRONLY | O_CLOEXEC));

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, read_end, 0);
    posix_spawn_file_actions_adddup2(&actions, null_fd, 1);
    posix_spawn_file_actions_adddup2(&actions, stderr_fd_, 2);
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 34)
    // Nothing else of ours (another worker's pipe, say) stays open in ffmpeg.
    posix_spawn_file_actions_addclosefrom_np(&actions, 3);
#endif
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, pipe;
    sigemptyset(&none);
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &pipe);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);

    std::vector<char*> argv;
    std::string argv0 = program.string();
    argv.push_back(argv0.data());
    std::vector<std::string> copies = args;
    for (std::string& a : copies) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int err =
        posix_spawn(&pid_, program.c_str(), &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    close(read_end);
    if (null_fd >= 0) close(null_fd);
    if (err != 0) {
      pid_ = -1;
      throw core::InputError("--video", "",
                             "cannot start " + program.string() + ": " + std::strerror(err));
    }
  }

  ~Encoder() {
    if (stdin_fd_ >= 0) close(stdin_fd_);
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      int status;
      while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
    }
    if (stderr_fd_ >= 0) close(stderr_fd_);
  }
  Encoder(const Encoder&) = delete;
  Encoder& operator=(const Encoder&) = delete;

  // False when ffmpeg no longer reads (it exited: EPIPE).
  bool write(const std::vector<std::uint8_t>& bytes) {
    const std::uint8_t* p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
      const ssize_t n = ::write(stdin_fd_, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        return false;
      }
      p += n;
      left -= static_cast<size_t>(n);
    }
    return true;
  }

  // Ends the input and reaps ffmpeg; its wait status.
  int finish() {
    close(stdin_fd_);
    stdin_fd_ = -1;
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0) {
      if (errno != EINTR) {
        status = -1;
        break;
      }
    }
    pid_ = -1;
    return status;
  }

  // The last non-empty line ffmpeg wrote to stderr.
  std::string last_error_line() const {
    std::string text;
    char buffer[4096];
    for (off_t at = 0;;) {
      const ssize_t n = pread(stderr_fd_, buffer, sizeof buffer, at);
      if (n <= 0) break;
      text.append(buffer, static_cast<size_t>(n));
      at += n;
      if (text.size() > (1u << 20)) text.erase(0, text.size() - (1u << 16));
    }
    std::string last, line;
    std::istringstream in(text);
    while (std::getline(in, line)) {
      const size_t cr = line.find_last_of('\r');
      if (cr != std::string::npos) line = line.substr(cr + 1);
      const size_t first = line.find_first_not_of(" \t");
      if (first != std::string::npos) last = line.substr(first);
    }
    return last;
  }

 private:
  pid_t pid_ = -1;
  int stdin_fd_ = -1;
  int stderr_fd_ = -1;
};

// Removes the file when destroyed, unless kept.
struct TemporaryFile {
  std::filesystem::path path;
  bool keep = false;
  ~TemporaryFile() {
    std::error_code ec;
    if (!keep) std::filesystem::remove(path, ec);
  }
};

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

namespace {

// The replay's current frame through `camera`, as PNG file bytes.
std::vector<std::uint8_t> render_png(Replay& replay, const core::Camera& camera,
                                     const FrameOptions& options) {
  return io::encode_png(replay.view().render(camera, options.width, options.height));
}

}  // namespace

std::vector<std::uint8_t> trial_snapshot_png(const ModelCatalog& catalog,
                                             const std::string& run_dir_and_trial, double time_s,
                                             const FrameOptions& options) {
  if (std::isnan(time_s)) throw core::InputError("--time", "", "not a number");
  const std::unique_ptr<Replay> replay = load_replay(catalog, run_dir_and_trial);
  std::string camera = options.camera;
  const core::Camera view = camera_view(replay->view(), camera);
  check_size(replay->view(), options, false);
  const size_t frame = time_s < 0 ? replay->frames() - 1 : replay->frame_at(time_s);
  replay->show(frame);
  return render_png(*replay, view, options);
}

namespace {

struct FocusCandidate {
  std::string label;
  std::string frame;  // the view's name of it
  bool palm = false;
  std::vector<Eigen::Vector3d> positions;  // per recorded frame up to the failure
};

// Largest distance of a candidate from where it was at `from` among frames from..to.
double moved(const FocusCandidate& c, size_t from, size_t to) {
  double most = 0;
  for (size_t k = from; k <= to; ++k) {
    most = std::max(most, (c.positions[k] - c.positions[from]).norm());
  }
  return most;
}

// The free camera `distance` from `target` at `azimuth` and `elevation` (degrees, MuJoCo's
// conventions: the camera looks along (cos el cos az, cos el sin az, sin el)).
core::Camera free_view(const Eigen::Vector3d& target, double distance, double azimuth,
                       double elevation) {
  core::Camera view;
  view.lookat = target;
  view.distance = distance;
  view.azimuth = std::fmod(std::fmod(azimuth, 360) + 360, 360);
  view.elevation = elevation;
  return view;
}

// Whether a free camera sees its look-at point: it is above the floor, and the ray from it to
// the point meets no visible geom (furniture, an obstacle, the robot's body; a camera inside a
// geom meets it at once) until within `near` of the point, where the hand and what it holds
// are.
bool sees_its_target(const core::SceneView& scene, const core::Camera& view, double near) {
  const double az = view.azimuth * std::numbers::pi / 180;
  const double el = view.elevation * std::numbers::pi / 180;
  const Eigen::Vector3d forward(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                std::sin(el));
  const Eigen::Vector3d eye = view.lookat - view.distance * forward;
  if (eye.z() < 0.05) return false;
  return scene.first_hit(eye, forward) >= view.distance - near;
}

}  // namespace

FailurePictures failure_pictures(const ModelCatalog& catalog, const std::string& run_dir_and_trial,
                                 double time_s, const FrameOptions& options) {
  if (std::isnan(time_s)) throw core::InputError("--time", "", "not a number");
  FailurePictures out;
  const std::unique_ptr<Replay> replay = load_replay(catalog, run_dir_and_trial);
  const core::LoadedScene& scene = replay->scene();
  core::SceneView& view = replay->view();
  std::string camera = options.camera;
  const core::Camera overview = camera_view(view, camera);
  check_size(view, options, false);
  const size_t frame = time_s < 0 ? replay->frames() - 1 : replay->frame_at(time_s);
  out.time_s = replay->time_of(frame);

  // Where the palms and the movable objects were at every frame up to the failure.
  std::vector<FocusCandidate> candidates;
  for (const core::HandSpec& hand : scene.robot().hands) {
    candidates.push_back({hand.side + " hand (" + hand.palm + ")", hand.palm, true, {}});
  }
  for (const auto& [name, object] : scene.environment().objects) {
    if (object.kind != core::ObjectKind::kGraspable && object.kind != core::ObjectKind::kTool) {
      continue;
    }
    candidates.push_back({name, name, false, {}});
  }
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  for (size_t k = 0; k <= frame; ++k) {
    replay->show(k);
    for (FocusCandidate& c : candidates) c.positions.push_back(view.position(c.frame));
    if (k == frame) base = view.base_position();
  }
  // A held or handled object: it moved during the trial and is at a palm now.
  const FocusCandidate* focus = nullptr;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  for (const FocusCandidate& object : candidates) {
    if (object.palm || moved(object, 0, frame) < 0.02) continue;
    for (const FocusCandidate& palm : candidates) {
      if (!palm.palm || (palm.positions[frame] - object.positions[frame]).norm() > 0.15) continue;
      focus = &object;
      target = (palm.positions[frame] + object.positions[frame]) / 2;
      out.focus = object.label + " (held or handled by the " + palm.label + ")";
    }
  }
  if (focus == nullptr) {
    // The palm that moved most just before the failure (over the whole trial if none did).
    const double window = 2.0;
    size_t from = frame;
    while (from > 0 && replay->time_of(from - 1) >= out.time_s - window) --from;
    for (const size_t start : {from, size_t{0}}) {
      double most = 0.01;
      for (const FocusCandidate& c : candidates) {
        if (!c.palm) continue;
        const double m = moved(c, start, frame);
        if (m > most) {
          most = m;
          focus = &c;
        }
      }
      if (focus != nullptr) break;
    }
    if (focus == nullptr && !candidates.empty() && candidates.front().palm) focus = &candidates[0];
    if (focus == nullptr) throw core::InputError("--trial", "", "the robot has no hands");
    target = focus->positions[frame];
    out.focus = focus->label;
    for (const FocusCandidate& object : candidates) {
      if (!object.palm && (object.positions[frame] - target).norm() <= 0.15) {
        target = (target + object.positions[frame]) / 2;
        out.focus += " at " + object.label;
        break;
      }
    }
  }
  // From beyond the focus as seen from the robot's base, looking back and down at it, turned
  // 35 degrees; where furniture, an obstacle or the robot's body would hide the focus (or the
  // camera would be inside something), turned further either way, then looking down more.
  replay->show(frame);
  const double towards_base =
      std::atan2(base.y() - target.y(), base.x() - target.x()) * 180 / std::numbers::pi;
  constexpr double kDistance = 0.7, kNear = 0.15;
  core::Camera close = free_view(target, kDistance, towards_base + 35, -25);
  bool found = false;
  for (const double elevation : {-25.0, -45.0, -65.0}) {
    for (const double turn : {35.0, -35.0, 70.0, -70.0, 105.0, -105.0, 140.0, -140.0, 180.0}) {
      // Judged through the view its --camera text describes, as it is drawn below.
      core::Camera candidate;
      parse_lookat(lookat_camera_text(free_view(target, kDistance, towards_base + turn, elevation)),
                   candidate);
      if (sees_its_target(view, candidate, kNear)) {
        close = candidate;
        found = true;
        break;
      }
    }
    if (found) break;
  }
  // Drawn through the view its --camera text describes, so that the text reproduces it.
  out.close_up_camera = lookat_camera_text(close);
  parse_lookat(out.close_up_camera, close);

  out.overview = render_png(*replay, overview, options);
  out.close_up = render_png(*replay, close, options);
  return out;
}

VideoInfo write_trial_video(const ModelCatalog& catalog, const std::string& run_dir_and_trial,
                            const std::filesystem::path& out, const VideoOptions& options) {
  if (!std::isfinite(options.fps) || options.fps <= 0 || options.fps > 1000) {
    throw core::InputError("--fps", "", number(options.fps) + " is not in (0, 1000]");
  }
  if (!std::isfinite(options.speed) || options.speed <= 0) {
    throw core::InputError("--speed", "", number(options.speed) + " is not a positive number");
  }
  if (out.empty() || out.filename().empty()) {
    throw core::InputError("--video", "", "'" + out.string() + "' is not a file name");
  }
  const std::filesystem::path folder = out.parent_path().empty() ? "." : out.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    throw core::InputError("--video", "",
                           "the output folder '" + folder.string() + "' does not exist");
  }
  if (std::filesystem::is_directory(out, ec)) {
    throw core::InputError("--video", "", "'" + out.string() + "' is a folder");
  }
  const std::filesystem::path ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    throw core::InputError("--video", "",
                           "ffmpeg is not on PATH (install the Debian package ffmpeg)");
  }

  const std::unique_ptr<Replay> replay = load_replay(catalog, run_dir_and_trial);
  VideoInfo info;
  info.camera = options.frame.camera;
  const core::Camera view = camera_view(replay->view(), info.camera);
  check_size(replay->view(), options.frame, true);

  const double t0 = replay->time_of(0);
  const double step = options.speed / options.fps;
  const double frames = std::floor((replay->time_of(replay->frames() - 1) - t0) / step + 1e-6) + 1;
  if (!(frames <= kMaxVideoFrames)) {
    throw core::InputError("--video", "",
                           "the trial would make " + number(frames) + " video frames (at most " +
                               number(kMaxVideoFrames) +
                               ", an hour at 25 fps): raise --speed or lower --fps");
  }
  info.frames = static_cast<size_t>(frames);
  info.duration_s = static_cast<double>(info.frames) / options.fps;

  static std::atomic<unsigned> serial{0};
  TemporaryFile partial{folder / ("." + out.filename().string() + ".part-" +
                                  std::to_string(getpid()) + "-" + std::to_string(serial++))};
  Encoder encoder(ffmpeg,
                  {"-hide_banner",
                   "-nostats",
                   "-loglevel",
                   "error",
                   "-y",
                   "-f",
                   "rawvideo",
                   "-pix_fmt",
                   "rgb24",
                   "-s",
                   std::to_string(options.frame.width) + "x" + std::to_string(options.frame.height),
                   "-r",
                   number(options.fps),
                   "-i",
                   "-",
                   "-an",
                   "-c:v",
                   "libx264",
                   "-pix_fmt",
                   "yuv420p",
                   "-movflags",
                   "+faststart",
                   "-f",
                   "mp4",
                   partial.path.string()});
  bool written = true;
  {
    const SigpipeBlocked blocked;
    size_t shown = replay->frames();
    core::RgbImage image;
    for (size_t k = 0; k < info.frames && written; ++k) {
      const size_t frame = replay->frame_at(t0 + static_cast<double>(k) * step);
      if (frame != shown) {
        replay->show(frame);
        image = replay->view().render(view, options.frame.width, options.frame.height);
        shown = frame;
      }
      written = encoder.write(image.pixels);
    }
  }
  const int status = encoder.finish();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !written) {
    const std::string line = encoder.last_error_line();
    std::string what = "no exit status";
    if (status != -1 && WIFEXITED(status)) {
      what = WEXITSTATUS(status) == 0 ? "it stopped reading frames"
                                      : "exit status " + std::to_string(WEXITSTATUS(status));
    } else if (status != -1 && WIFSIGNALED(status)) {
      what = "killed by signal " + std::to_string(WTERMSIG(status));
    }
    throw core::InputError("--video", "",
                           "ffmpeg failed (" + what + ")" + (line.empty() ? "" : ": " + line));
  }
  std::filesystem::rename(partial.path, out);
  partial.keep = true;
  return info;
}

}  // namespace taskmatrix::harness
