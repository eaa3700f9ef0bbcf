// explore: moves the head (and the base's yaw) so that the head sensor observes a region
// (paper: "explore"). The region is the top face of a known surface, or explicit bounds; it
// is divided into square cells. A cell is observed when a depth ray of the head sensor ends
// in its column (within `column_m` above the region): on the surface or on whatever stands
// on it.
//
// Viewpoints: a grid over the head joints, and with the base free, base yaw turns of
// +-0.5 and +-1.0 rad. A robot without a head chain (its camera fixed to the trunk) has base
// turns alone, in steps of 0.5 rad up to +-3 rad, each also from 0.3 m back; with the base
// not free either, it looks once from where it stands. After each scan, the next viewpoint is the
// one whose camera frustum holds the most cells not yet observed (ties: the closest in joint
// space); cells that were in the frustum of two viewpoints without being observed count as
// unobservable (occluded, out of range) and are not chased further. Motion to a viewpoint is
// planned (collision-free); a viewpoint in collision (an arm swept into furniture by a base turn)
// is taken from a base moved away from where it stands (up to 0.45 m). When nothing from where
// the robot stands shows a new cell, once, the base is free to walk round the region: 8 base
// poses round it facing its centre, as far outside its edge as the robot stands now (0.25 to
// 0.6 m), with the head grid; the cells given up on count again.
//
// Records "coverage" (observed cells / all cells) after every scan. Completes when coverage
// reaches `coverage`; fails with "coverage_short: ..." when no viewpoint promises a new cell
// or `time_limit` passes, reporting what was reached.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

constexpr double kScanPeriod = 0.2;      // s between scans while moving
constexpr double kMaxCells = 1e6;        // a 10 m x 10 m region in 1 cm cells
constexpr double kMaxCoordinate = 1000;  // m

struct Region {
  double x0, x1, y0, y1, z;
};

class Explore final : public core::TaskProgram {
 public:
  explicit Explore(const core::Params& p)
      : surface_(p.text("surface")),
        bounds_(p.list("bounds")),
        cell_(p.number("cell_m")),
        target_(p.number("coverage")),
        time_limit_(p.number("time_limit")),
        use_base_(p.flag("base")) {
    if (surface_.empty() == bounds_.empty()) {
      throw std::invalid_argument("explore needs exactly one of surface and bounds");
    }
    if (!bounds_.empty() && bounds_.size() != 5) {
      throw std::invalid_argument(
          "parameter 'bounds': five numbers [x_min, x_max, y_min, y_max, z] in metres");
    }
    if (!(cell_ >= 0.01 && cell_ <= 1.0)) {
      throw std::invalid_argument("parameter 'cell_m': must be in [0.01, 1] m");
    }
    if (!(target_ > 0 && target_ <= 1)) {
      throw std::invalid_argument("parameter 'coverage': must be in (0, 1]");
    }
    if (!(time_limit_ > 0 && std::isfinite(time_limit_))) {
      throw std::invalid_argument("parameter 'time_limit': must be positive");
    }
  }

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return head_chains(skills);
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    base_ = use_base_;
    std::vector<std::string> out = head_claim(ctx, base_);
    // A torso an earlier program left bent (a putdown bends it over the table) points the
    // head camera at the floor: the viewpoints bring it back to its rest posture too.
    torso_rest_.clear();
    if (base_ && ctx.skills.profile().find_chain("torso") && !ctx.busy("torso")) {
      const std::vector<double> rest = posture_values(ctx.skills, "rest", {"torso"}).values;
      if (max_difference(rest, ctx.skills.configuration({"torso"})) > kBentTorso) {
        torso_rest_ = rest;
        out.insert(out.end() - 1, "torso");
      }
    }
    return out;
  }

  void start(core::ProgramContext& ctx) override {
    failure_ = make_region(ctx);
    if (failure_) return;
    // Cells are counted in doubles first: a wide region with small cells must not overflow.
    const double cx = std::max(1.0, std::round((region_.x1 - region_.x0) / cell_));
    const double cy = std::max(1.0, std::round((region_.y1 - region_.y0) / cell_));
    if (!(cx * cy <= kMaxCells)) {
      failure_ = core::Failure(core::FailureCode::kInvalidInput,
                               "the region holds " + number(cx * cy) + " cells of " +
                                   number(cell_) + " m (at most " + number(kMaxCells) + ")");
      return;
    }
    nx_ = static_cast<int>(cx);
    ny_ = static_cast<int>(cy);
    observed_.assign(static_cast<size_t>(nx_) * ny_, 0);
    missed_.assign(observed_.size(), 0);
    start_time_ = ctx.time();
    chains_ = head_chains(ctx.skills());
    if (!torso_rest_.empty()) chains_.push_back("torso");
    if (base_) chains_.push_back("base");
    scan(ctx);
    if (chains_.empty()) {
      // No head chain and the base not free: one look from where the robot stands.
      if (coverage() < target_ - 1e-12) {
        failure_ = shortfall("nothing aims the camera (the robot has no head chain; base: false)");
      }
      return;
    }
    // What the first look shows may be enough: no viewpoint is sought (one that could not be
    // reached would fail a region already covered).
    if (coverage() >= target_ - 1e-12) return;
    make_viewpoints(ctx.skills());
    next_viewpoint(ctx);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (coverage() >= target_ - 1e-12) return core::ProgramState::kCompleted;
    if (failure_) return fail(*failure_);
    if (ctx.time() - start_time_ >= time_limit_) {
      return fail(shortfall("the time limit of " + number(time_limit_) + " s passed"));
    }
    if (ctx.time() >= next_scan_ - 1e-9) scan(ctx);
    const std::optional<Ended> moved = motion_.step();
    if (!moved) return core::ProgramState::kRunning;
    if (*moved) return fail(**moved);
    // At a viewpoint: look, then choose the next one.
    scan(ctx);
    for (size_t c : expected_) {
      if (!observed_[c]) ++missed_[c];
    }
    if (coverage() >= target_ - 1e-12) return core::ProgramState::kCompleted;
    next_viewpoint(ctx);
    if (failure_) return fail(*failure_);
    return core::ProgramState::kRunning;
  }

 private:
  static std::string number(double v) {
    std::ostringstream s;
    s.precision(3);
    s << v;
    return s.str();
  }

  std::optional<core::Failure> make_region(core::ProgramContext& ctx) {
    if (!bounds_.empty()) {
      double v[5];
      for (int i = 0; i < 5; ++i) {
        try {
          size_t used = 0;
          v[i] = std::stod(bounds_[i], &used);
          if (used != bounds_[i].size() || !std::isfinite(v[i])) throw std::invalid_argument("");
        } catch (const std::exception&) {
          return core::Failure(
              core::FailureCode::kInvalidInput,
              "bounds[" + std::to_string(i) + "] '" + bounds_[i] + "' is not a number");
        }
      }
      if (!(v[0] < v[1] && v[2] < v[3]))
        return core::Failure(core::FailureCode::kInvalidInput, "bounds must have min < max");
      if (!std::all_of(v, v + 5, [](double x) { return std::abs(x) <= kMaxCoordinate; })) {
        return core::Failure(core::FailureCode::kInvalidInput,
                             "bounds must lie within 1000 m of the origin");
      }
      region_ = {v[0], v[1], v[2], v[3], v[4]};
      return std::nullopt;
    }
    const core::PerceivedObject* s = ctx.percepts().find(surface_);
    if (!s)
      return core::Failure(core::FailureCode::kPerceptionMiss,
                           "'" + surface_ + "' is not in the perceptual model");
    region_ = {s->box.min().x(), s->box.max().x(), s->box.min().y(), s->box.max().y(),
               s->box.max().z()};
    return std::nullopt;
  }

  Eigen::Vector3d cell_centre(size_t c) const {
    const int ix = static_cast<int>(c) % nx_, iy = static_cast<int>(c) / nx_;
    const double wx = (region_.x1 - region_.x0) / nx_, wy = (region_.y1 - region_.y0) / ny_;
    return {region_.x0 + (ix + 0.5) * wx, region_.y0 + (iy + 0.5) * wy, region_.z};
  }

  double coverage() const {
    if (observed_.empty()) return 0;  // no region (start failed)
    return static_cast<double>(std::count(observed_.begin(), observed_.end(), 1)) /
           static_cast<double>(observed_.size());
  }

  core::Failure shortfall(const std::string& why) const {
    const auto seen = std::count(observed_.begin(), observed_.end(), 1);
    return core::Failure(core::FailureCode::kCoverageShort,
                         "observed " + std::to_string(seen) + " of " +
                             std::to_string(observed_.size()) + " cells (coverage " +
                             number(coverage()) + ", target " + number(target_) + "); " + why);
  }

  void scan(core::ProgramContext& ctx) {
    const core::DepthScan depth = ctx.skills().scan_depth();
    const double wx = (region_.x1 - region_.x0) / nx_, wy = (region_.y1 - region_.y0) / ny_;
    for (const Eigen::Vector3d& p : depth.hits) {
      if (p.z() < region_.z - 0.02 || p.z() > region_.z + column_m_) continue;
      const int ix = static_cast<int>(std::floor((p.x() - region_.x0) / wx));
      const int iy = static_cast<int>(std::floor((p.y() - region_.y0) / wy));
      if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) continue;
      observed_[static_cast<size_t>(iy) * nx_ + ix] = 1;
    }
    ctx.record("coverage", coverage());
    next_scan_ = ctx.time() + kScanPeriod;
  }

  void make_viewpoints(core::Skillset& skills) {
    const std::vector<double> now = skills.configuration(chains_);
    const bool has_head = chains_.front() == "head";
    const core::ChainInfo* head = has_head ? &skills.chain("head") : nullptr;
    const size_t n = has_head ? head->joints.size() : 0;
    const int steps = n == 1 ? 9 : 5;
    std::vector<std::vector<double>> heads{{}};
    for (size_t j = 0; j < n; ++j) {
      std::vector<std::vector<double>> next;
      for (const auto& partial : heads) {
        for (int k = 0; k < steps; ++k) {
          std::vector<double> q = partial;
          q.push_back(head->lower[j] + (head->upper[j] - head->lower[j]) * (k + 0.5) / steps);
          next.push_back(q);
        }
      }
      heads.swap(next);
    }
    heads_ = heads;
    // Without a head the base does all the aiming: turns all the way round, each also from
    // 0.3 m back along the new heading (a fixed camera sees nothing close below it).
    std::vector<double> turns{0.0}, backs{0.0};
    if (base_ && has_head) {
      turns = {0.0, -0.5, 0.5, -1.0, 1.0};
      // A region beside or behind the robot (after a putdown on another surface): the turn
      // that faces its centre, and half a radian either side of it.
      if (now.size() >= n + 3) {
        const std::vector<double> b(now.end() - 3, now.end());
        const double facing = std::remainder(std::atan2(0.5 * (region_.y0 + region_.y1) - b[1],
                                                        0.5 * (region_.x0 + region_.x1) - b[0]) -
                                                 b[2],
                                             2 * M_PI);
        if (std::abs(facing) > 1.0) {
          for (double t : {facing, facing - 0.5, facing + 0.5}) turns.push_back(t);
        }
      }
    }
    if (base_ && !has_head) {
      for (int k = 1; k <= 6; ++k) {
        turns.push_back(-0.5 * k);
        turns.push_back(0.5 * k);
      }
      backs.push_back(0.3);
    }
    const core::ChainInfo* base = base_ ? &skills.chain("base") : nullptr;
    for (double back : backs) {
      for (double turn : turns) {
        for (const auto& hq : heads) {
          std::vector<double> v = hq;
          v.insert(v.end(), torso_rest_.begin(), torso_rest_.end());
          if (base) {
            std::vector<double> b(now.begin() + static_cast<long>(n + torso_rest_.size()),
                                  now.end());
            if (b.size() != 3) continue;
            const std::optional<double> heading = heading_within_limits(*base, b[2] + turn);
            if (!heading) continue;
            b[2] = *heading;
            b[0] -= back * std::cos(b[2]);
            b[1] -= back * std::sin(b[2]);
            v.insert(v.end(), b.begin(), b.end());
          }
          viewpoints_.push_back(v);
        }
      }
    }
  }

  // Cells a viewpoint would see, by the camera frustum (no occlusion).
  std::vector<size_t> in_view(core::Skillset& skills, const std::vector<double>& v) const {
    const core::CameraInfo cam = skills.head_camera();
    const core::Pose pose = skills.frame_pose_at(chains_, v, cam.frame);
    const double t = std::tan(cam.fovy_rad / 2);
    std::vector<size_t> cells;
    for (size_t c = 0; c < observed_.size(); ++c) {
      const Eigen::Vector3d p = pose.orientation.conjugate() * (cell_centre(c) - pose.position);
      const double ahead = -p.z();
      if (ahead <= 0 || p.norm() > cam.range_m) continue;
      if (std::abs(p.y()) <= 0.9 * ahead * t && std::abs(p.x()) <= 0.9 * ahead * t * cam.aspect)
        cells.push_back(c);
    }
    return cells;
  }

  // A viewpoint whose configuration is in collision (a base turn sweeping an arm into the
  // furniture beside the robot): the same head and turn from a base moved away by up to
  // 0.45 m, in the first of eight directions (backwards first) that is collision-free and
  // still shows a cell not yet observed. Nothing if none is.
  std::optional<std::vector<double>> clear_variant(core::Skillset& skills,
                                                   const std::vector<double>& v) const {
    if (!base_) return std::nullopt;
    const size_t n = v.size() - 3;  // the head's joints come first, then base x, y, yaw
    const double heading = v[n + 2];
    for (double d : {0.1, 0.2, 0.3, 0.45}) {
      for (double a : {M_PI, 0.75 * M_PI, -0.75 * M_PI, 0.5 * M_PI, -0.5 * M_PI, 0.25 * M_PI,
                       -0.25 * M_PI, 0.0}) {
        std::vector<double> w = v;
        w[n] += d * std::cos(heading + a);
        w[n + 1] += d * std::sin(heading + a);
        if (!skills.is_valid(chains_, w)) continue;
        for (size_t c : in_view(skills, w)) {
          if (!observed_[c] && missed_[c] < 2) return w;
        }
      }
    }
    return std::nullopt;
  }

  // Viewpoints from base poses round the region (kRoundPoses directions from its centre),
  // each as far outside its edge as the base stands from the edge now (kRoundStandoffM at
  // least and at most), facing its centre, with every head position of the grid and the torso
  // as in the other viewpoints. False when the base is not free or none is within its limits.
  bool add_viewpoints_round(core::Skillset& skills) {
    if (!base_ || heads_.empty()) return false;
    const core::ChainInfo& base = skills.chain("base");
    const std::vector<double> b = skills.configuration({"base"});
    const double cx = 0.5 * (region_.x0 + region_.x1), cy = 0.5 * (region_.y0 + region_.y1);
    const double hx = 0.5 * (region_.x1 - region_.x0), hy = 0.5 * (region_.y1 - region_.y0);
    const double outside = std::hypot(std::max({region_.x0 - b[0], 0.0, b[0] - region_.x1}),
                                      std::max({region_.y0 - b[1], 0.0, b[1] - region_.y1}));
    const double standoff = std::clamp(outside, kRoundStandoffM[0], kRoundStandoffM[1]);
    const size_t before = viewpoints_.size();
    for (int k = 0; k < kRoundPoses; ++k) {
      const double a = 2 * M_PI * k / kRoundPoses, c = std::cos(a), sn = std::sin(a);
      // From the centre to the region's edge along (c, sn), then the standoff beyond it.
      const double edge = std::min(std::abs(c) > 1e-9 ? hx / std::abs(c) : INFINITY,
                                   std::abs(sn) > 1e-9 ? hy / std::abs(sn) : INFINITY);
      const std::optional<double> heading =
          heading_within_limits(base, b[2] + std::remainder(a + M_PI - b[2], 2 * M_PI));
      if (!heading) continue;
      const std::vector<double> pose = {cx + (edge + standoff) * c, cy + (edge + standoff) * sn,
                                        *heading};
      bool within = true;
      for (size_t j = 0; j < 2; ++j) {
        within = within && pose[j] >= base.lower[j] && pose[j] <= base.upper[j];
      }
      if (!within) continue;
      for (const std::vector<double>& h : heads_) {
        std::vector<double> v = h;
        v.insert(v.end(), torso_rest_.begin(), torso_rest_.end());
        v.insert(v.end(), pose.begin(), pose.end());
        viewpoints_.push_back(std::move(v));
      }
    }
    return viewpoints_.size() > before;
  }

  // Plans to the most promising viewpoint; an unreachable one is skipped for the next best.
  // A viewpoint in collision is replaced by its clear variant (or dropped) before planning,
  // so that only plans count against the six attempts.
  void next_viewpoint(core::ProgramContext& ctx) {
    core::Skillset& skills = ctx.skills();
    const std::vector<double> now = skills.configuration(chains_);
    // A hand left against what it has just set down (a putdown before): the torso and base
    // carry it away, and the plan may brush that object near its start, as retreat's does
    // (what the arms touch now, not what they touched before an earlier viewpoint).
    motion_.execution.may_touch.clear();
    for (const char* side : {"left", "right"}) motion_.allow_touching(touched_by_arm(ctx, side));
    std::string unreachable;
    for (int attempt = 0; attempt < 6;) {
      int best = -1;
      size_t best_gain = 0;
      double best_dist = 0;
      std::vector<size_t> best_cells;
      for (size_t k = 0; k < viewpoints_.size(); ++k) {
        if (visited_.count(k)) continue;
        std::vector<size_t> cells = in_view(skills, viewpoints_[k]);
        size_t gain = 0;
        for (size_t c : cells) gain += !observed_[c] && missed_[c] < 2;
        const double dist = max_difference(viewpoints_[k], now);
        if (gain > best_gain || (gain == best_gain && gain > 0 && dist < best_dist)) {
          best = static_cast<int>(k), best_gain = gain, best_dist = dist;
          best_cells = std::move(cells);
        }
      }
      if (best < 0) {
        // Nothing from where the robot stands shows more (a short robot's fixed tilt sees
        // only the near half of a deep table): once, viewpoints round the region, and the
        // cells given up on are tried again from there.
        const size_t near = viewpoints_.size();
        if (walked_round_ || !add_viewpoints_round(skills)) break;
        walked_round_ = true;
        for (size_t k = 0; k < near; ++k) visited_.insert(k);  // they showed what they could
        std::fill(missed_.begin(), missed_.end(), 0);
        continue;
      }
      visited_.insert(static_cast<size_t>(best));
      std::vector<double> goal = viewpoints_[static_cast<size_t>(best)];
      if (!skills.is_valid(chains_, goal)) {
        const std::optional<std::vector<double>> clear = clear_variant(skills, goal);
        if (!clear) {
          unreachable =
              "every viewpoint showing more is in collision, also from a base moved "
              "up to 0.45 m";
          continue;
        }
        goal = *clear;
        best_cells = in_view(skills, goal);
      }
      ++attempt;
      const std::optional<core::Failure> planned =
          motion_.plan_to_configuration(ctx, chains_, goal);
      if (!planned) {
        expected_ = std::move(best_cells);
        return;
      }
      unreachable = planned->reason();
    }
    failure_ =
        shortfall(unreachable.empty() ? "no viewpoint shows a cell not yet observed"
                                      : "the viewpoints that would show more cannot be reached (" +
                                            unreachable + ")");
  }

  std::string surface_;
  std::vector<std::string> bounds_;
  double cell_, target_, time_limit_;
  bool use_base_, base_ = false;
  // The torso's rest posture where explore straightens it (empty: the torso is not moved).
  std::vector<double> torso_rest_;
  static constexpr double kBentTorso = 0.05;  // rad from rest: a torso left bent
  double column_m_ = 0.5;
  Region region_{};
  int nx_ = 1, ny_ = 1;
  std::vector<char> observed_;
  std::vector<int> missed_;
  std::vector<size_t> expected_;
  std::vector<std::string> chains_;
  std::vector<std::vector<double>> viewpoints_;
  std::vector<std::vector<double>> heads_;  // the grid over the head joints
  bool walked_round_ = false;               // the viewpoints round the region were added
  static constexpr int kRoundPoses = 8;
  static constexpr double kRoundStandoffM[2] = {0.25, 0.6};
  std::set<size_t> visited_;
  double start_time_ = 0, next_scan_ = 0;
  MotionStage motion_;
  std::optional<core::Failure> failure_;
};

}  // namespace

core::ProgramType explore_program() {
  using core::ParamType;
  return {"explore",
          "moves the head (and base) so that the head sensor observes a region; records "
          "coverage over time",
          {{"surface",
            ParamType::kString,
            false,
            std::string(),
            {},
            "a known surface's top",
            core::NameKind::kObject},
           {"bounds",
            ParamType::kStringList,
            false,
            std::vector<std::string>{},
            {},
            "or a region [x_min, x_max, y_min, y_max, z] (m)"},
           {"cell_m", ParamType::kNumber, false, 0.05, {}, "cell size (m)"},
           {"coverage", ParamType::kNumber, false, 0.9, {}, "target share of cells observed"},
           {"time_limit", ParamType::kNumber, false, 60.0, {}, "simulated seconds"},
           {"base", ParamType::kBool, false, true, {}, "turn the base too (if the base is free)"}},
          [](const core::Params& p) { return std::make_unique<Explore>(p); }};
}

}  // namespace taskmatrix::programs
