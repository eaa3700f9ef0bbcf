#include "taskmatrix/programs/grasp_candidates.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace taskmatrix::programs {

namespace {

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// A fit above this share of the aperture is tight: the fingers barely pass the object.
constexpr double kLooseFit = 0.85;
// Widths vary by less than this around a round object.
constexpr double kRoundTolerance = 0.003;
// How far the hand may turn about a free axis and still fit: the width must stay under
// this share of the aperture, turning at most kMaxTurn.
constexpr double kTurnFit = 0.9;
constexpr double kMaxTurn = 0.35;
// How far the fingers stay over the surface the object stands on, and the share of the
// approach that is downward for the hand to stop short of that surface.
constexpr double kSupportClearance = 0.005;
constexpr double kDownward = 0.1;
constexpr double kSettle = 0.003;
constexpr double kGraspableReach = 0.03 - kSettle;
// The closing sweep's step (the angle the joint that turns most turns per step).
constexpr double kSweepStepRad = 0.2;
// A finger's first segment slides (a parallel jaw) when, from open to `fist`, it turns less
// than kSlideTurnRad and moves more than kSlideMinM.
constexpr double kSlideTurnRad = 0.01;
constexpr double kSlideMinM = 0.005;
// A handle is ringed when, seen along its axis, no gap round it between the hand's points is
// wider than a half-turn less this.
constexpr double kRingMarginRad = 0.1;
// Side grasps raised by this above the object's middle, if that is at most this share of the
// way to its top (fallback candidates).
constexpr double kRaiseM = 0.02;
constexpr double kMaxRaiseShare = 0.5;
constexpr double kRaisedCost = 30.0;
// A candidate wider than the aperture is kept where the fingers wrap it with the palm this far
// off its near side (the nearer of reach's clearances); HandGeometry::wraps looks at each
// finger segment in this many pieces.
constexpr double kWrapClearance = 0.01;
constexpr int kWrapPieces = 8;
// The parts of an object (core::protruding_shapes), grasped on their own.
constexpr double kPartCost = 5.0;
constexpr double kPartObliqueRad = 0.6;

Eigen::Vector3d horizontal(Eigen::Vector3d v) {
  v.z() = 0;
  return v.norm() < 1e-9 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(v.normalized());
}

Eigen::Vector3d yawed(const Eigen::Vector3d& v, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * v;
}

// The object's geometry: its shapes, or its box when perception gives no shapes.
class Geometry {
 public:
  explicit Geometry(const core::PerceivedObject& o) : shapes_(o.shapes) {
    if (shapes_.empty()) {
      core::Shape box;
      box.type = core::Shape::Type::kBox;
      box.pose.position = o.box.center();
      box.size = o.box.sizes() / 2;
      shapes_.push_back(box);
    }
  }
  const std::vector<core::Shape>& shapes() const { return shapes_; }
  // The interval the object covers along unit direction `u` (as u . x).
  std::pair<double, double> extent(const Eigen::Vector3d& u) const { return extent_of(shapes_, u); }
  static std::pair<double, double> extent_of(const std::vector<core::Shape>& shapes,
                                             const Eigen::Vector3d& u) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const core::Shape& s : shapes) {
      const double c = s.pose.position.dot(u), h = s.half_width(u);
      lo = std::min(lo, c - h);
      hi = std::max(hi, c + h);
    }
    return {lo, hi};
  }
  double width(const Eigen::Vector3d& u) const {
    const auto [lo, hi] = extent(u);
    return hi - lo;
  }
  Eigen::Vector3d centre() const {
    Eigen::Vector3d c;
    for (int i = 0; i < 3; ++i) {
      const auto [lo, hi] = extent(Eigen::Vector3d::Unit(i));
      c[i] = 0.5 * (lo + hi);
    }
    return c;
  }
  // True when the horizontal widths are the same all round (a cylinder standing up).
  bool round() const {
    double lo = INFINITY, hi = 0;
    for (int k = 0; k < 12; ++k) {
      const double w = width(yawed(Eigen::Vector3d::UnitX(), k * M_PI / 12));
      lo = std::min(lo, w);
      hi = std::max(hi, w);
    }
    return hi - lo < kRoundTolerance;
  }

 private:
  std::vector<core::Shape> shapes_;
};

// How far (up to kMaxTurn) `closing` may turn about the vertical with the width across the
// shapes staying under kTurnFit of the aperture.
double free_turn(const std::vector<core::Shape>& shapes, const Eigen::Vector3d& closing,
                 double aperture) {
  double turn = 0;
  for (double t = 0.05; t <= kMaxTurn + 1e-9; t += 0.05) {
    bool fits = true;
    for (double sign : {-1.0, 1.0}) {
      const auto [lo, hi] = Geometry::extent_of(shapes, yawed(closing, sign * t));
      fits = fits && hi - lo <= kTurnFit * aperture;
    }
    if (!fits) break;
    turn = t;
  }
  return turn;
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}

// The shape nearest to `point` (distance to its centre, or to the axis segment of a capsule
// or cylinder).
const core::Shape& nearest_shape(const std::vector<core::Shape>& shapes,
                                 const Eigen::Vector3d& point) {
  const core::Shape* best = &shapes.front();
  double best_d = INFINITY;
  for (const core::Shape& s : shapes) {
    Eigen::Vector3d c = s.pose.position;
    if (s.type == core::Shape::Type::kCapsule || s.type == core::Shape::Type::kCylinder) {
      const Eigen::Vector3d axis = s.pose.orientation * Eigen::Vector3d::UnitZ();
      c += std::clamp((point - c).dot(axis), -s.size.y(), s.size.y()) * axis;
    }
    const double d = (point - c).norm();
    if (d < best_d) best_d = d, best = &s;
  }
  return *best;
}

}  // namespace

HandGeometry measure_hand(core::Skillset& skills, const core::HandSpec& hand) {
  HandGeometry g;
  g.side = hand.side;
  g.approach = vec(hand.approach).normalized();
  g.closing = vec(hand.closing).normalized();
  const std::string chain = hand.side + "_hand";
  // The hand open (or at rest, for a profile without an open posture).
  std::vector<double> open = skills.configuration({chain});
  for (const char* name : {"rest", "hand_open"}) {
    const auto posture = skills.profile().postures.find(name);
    if (posture != skills.profile().postures.end() && posture->second.count(chain)) {
      open = posture->second.at(chain);
    }
  }
  std::vector<double> closed = open;
  const auto fist = skills.profile().postures.find("fist");
  if (fist != skills.profile().postures.end() && fist->second.count(chain)) {
    closed = fist->second.at(chain);
  }
  // A body's pose in the palm frame, with the hand at `config`.
  auto pose_in_palm = [&](const std::vector<double>& config, const std::string& body) {
    const core::Pose p = skills.frame_pose_at({chain}, config, body);
    const core::Pose at = skills.frame_pose_at({chain}, config, hand.palm);
    core::Pose out;
    out.orientation = at.orientation.conjugate() * p.orientation;
    out.position = at.orientation.conjugate() * (p.position - at.position);
    return out;
  };
  auto in_palm = [&](const std::vector<double>& config, const std::string& body) {
    return pose_in_palm(config, body).position;
  };
  double lo = INFINITY, hi = -INFINITY, depth = 0, reach = 0;
  std::optional<double> palm_depth;  // asked of the skillset once, for the first sliding finger
  // The closing in steps of kSweepStepRad of the joint that turns most per step: each joint
  // moves towards the fist by the same angle until it gets there.
  double widest = 0;
  for (size_t j = 0; j < open.size() && j < closed.size(); ++j) {
    widest = std::max(widest, std::abs(closed[j] - open[j]));
  }
  const int steps = std::max(1, static_cast<int>(std::ceil(widest / kSweepStepRad)));
  std::vector<std::vector<double>> sweep;
  for (int s = 0; s <= steps; ++s) {
    std::vector<double> q = open;
    for (size_t j = 0; j < q.size() && j < closed.size(); ++j) {
      const double turn = std::min(widest * s / steps, std::abs(closed[j] - open[j]));
      q[j] += closed[j] >= open[j] ? turn : -turn;
    }
    sweep.push_back(std::move(q));
  }
  for (const core::FingerSpec& f : hand.fingers) {
    if (f.bodies.empty()) continue;
    const Eigen::Vector3d base = in_palm(open, f.bodies.front());
    lo = std::min(lo, base.dot(g.closing));
    hi = std::max(hi, base.dot(g.closing));
    // A finger that turns closes from its root, about where the palm is. One whose first
    // segment slides without turning (a parallel jaw) may have its frame anywhere along the
    // approach: there the palm's own geometry tells where an object stops.
    const core::Pose root_open = pose_in_palm(open, f.bodies.front());
    const core::Pose root_closed = pose_in_palm(closed, f.bodies.front());
    const bool slides =
        root_open.orientation.angularDistance(root_closed.orientation) < kSlideTurnRad &&
        (root_closed.position - root_open.position).norm() > kSlideMinM;
    if (slides && !palm_depth) palm_depth = skills.palm_depth(hand.side);
    depth += slides ? *palm_depth : -base.dot(g.approach);
    reach += in_palm(closed, f.bodies.back()).dot(g.approach);
    // The open finger, about straight: its segments' origins and its tip, estimated from the
    // segment before the last. (Closing, the fingers curl towards the object and stop on it.)
    Eigen::Vector3d previous = Eigen::Vector3d::Zero(), last = Eigen::Vector3d::Zero();
    for (const std::string& body : f.bodies) {
      previous = last;
      last = in_palm(open, body);
      g.finger_points.push_back(last);
    }
    if (f.bodies.size() >= 2) g.finger_points.push_back(2 * last - previous);
    // The fingertip estimate rides on the last segment as the finger closes.
    const core::Pose last_open = pose_in_palm(open, f.bodies.back());
    const Eigen::Vector3d tip_in_last =
        f.bodies.size() >= 2
            ? Eigen::Vector3d(last_open.orientation.conjugate() * (last - previous))
            : Eigen::Vector3d::Zero();
    std::vector<std::vector<Eigen::Vector3d>> finger_sweep;
    for (const std::vector<double>& q : sweep) {
      std::vector<Eigen::Vector3d> points;
      core::Pose end;  // the last segment's, once the loop is done
      for (const std::string& body : f.bodies) {
        end = pose_in_palm(q, body);
        points.push_back(end.position);
      }
      points.push_back(end.position + end.orientation * tip_in_last);
      finger_sweep.push_back(std::move(points));
    }
    g.sweeps.push_back(std::move(finger_sweep));
    g.tips_in_last.push_back(tip_in_last);
    ++g.fingers;
  }
  g.aperture_m = g.fingers >= 2 ? hi - lo : 0;
  g.palm_depth_m = g.fingers > 0 ? std::max(0.0, depth / g.fingers) : 0;
  g.closed_reach_m = g.fingers > 0 ? std::max(0.0, reach / g.fingers) : 0;
  g.fingers_needed = std::min(g.fingers, g.fingers / 2 + 1);
  return g;
}

std::vector<Eigen::Vector3d> HandGeometry::swept_points(const Eigen::Vector3d& centre,
                                                        const Eigen::Vector3d& axis,
                                                        double radius) const {
  const Eigen::Vector3d u = axis.normalized();
  // The distance from the segment a-b to the line.
  auto from_line = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Eigen::Vector3d pa = a - centre, pb = b - centre;
    pa -= pa.dot(u) * u;
    pb -= pb.dot(u) * u;
    const Eigen::Vector3d d = pb - pa;
    const double t =
        d.squaredNorm() > 1e-12 ? std::clamp(-pa.dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    return (pa + t * d).norm();
  };
  std::vector<Eigen::Vector3d> out;
  for (const std::vector<std::vector<Eigen::Vector3d>>& finger : sweeps) {
    for (const std::vector<Eigen::Vector3d>& points : finger) {
      out.insert(out.end(), points.begin(), points.end());
      bool stopped = false;
      for (size_t i = 0; radius > 0 && i + 1 < points.size(); ++i) {
        stopped = stopped || from_line(points[i], points[i + 1]) <= radius;
      }
      if (stopped) break;
    }
  }
  return out;
}

bool HandGeometry::wraps(double width, double length, double ahead) const {
  const double r = width / 2;
  const Eigen::Vector3d centre = ahead * approach;
  const Eigen::Vector3d across = approach.cross(closing).normalized();
  // A point of the segment a-b inside the section, if any.
  auto inside = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    std::optional<Eigen::Vector3d> hit;
    for (int i = 0; i <= kWrapPieces && !hit; ++i) {
      const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(i) / kWrapPieces) - centre;
      const double along = p.dot(across);
      if (std::abs(along) <= length / 2 && (p - along * across).norm() <= r) hit = p;
    }
    return hit;
  };
  int meeting = 0;
  bool before = false, after = false;  // met on either side of the middle, along closing
  bool beyond = false;  // met past the middle, along approach: holding it against the palm
  for (const std::vector<std::vector<Eigen::Vector3d>>& finger : sweeps) {
    for (size_t step = 0; step < finger.size(); ++step) {
      std::optional<Eigen::Vector3d> at;
      for (size_t i = 0; i + 1 < finger[step].size() && !at; ++i) {
        at = inside(finger[step][i], finger[step][i + 1]);
      }
      if (!at) continue;
      if (step == 0) return false;  // the open finger is in the object's way
      ++meeting;
      (at->dot(closing) < 0 ? before : after) = true;
      beyond = beyond || at->dot(approach) >= 0;
      break;
    }
  }
  return meeting >= fingers_needed && before && after && beyond;
}

bool GraspCandidate::wrapped_at(const HandGeometry& hand, double clearance) const {
  const double ahead =
      std::max({0.0, width_m / 2 + clearance - hand.palm_depth_m, hand.closed_reach_m});
  return wrap_length_m <= 0 || hand.wraps(width_m, wrap_length_m, ahead);
}

GraspCandidate::Placement GraspCandidate::place(const HandGeometry& hand, double clearance) const {
  Eigen::Matrix3d palm, world;
  const Eigen::Vector3d across = approach.cross(closing).normalized();
  palm << hand.approach, hand.closing, hand.approach.cross(hand.closing);
  world << approach, closing.normalized(), across;
  double back = std::max({0.0, half_depth_m + clearance - hand.palm_depth_m, hand.closed_reach_m});
  Placement p;
  p.pose.orientation = Eigen::Quaterniond(world * palm.transpose()).normalized();
  double lowest = INFINITY;  // the lowest finger point with the palm frame at `centre`
  for (const Eigen::Vector3d& f : hand.finger_points) {
    lowest = std::min(lowest, centre.z() + (p.pose.orientation * f).z());
  }
  const double gap = lowest - back * approach.z() - support_z;
  // Coming down (from above or obliquely), the hand stops with its fingers over the support.
  // Not beyond where graspable() finds the palm: within 3 cm of the grasp point, or inside the
  // box of an object that is no tool (less the 3 mm the arm settles within).
  const double max_back =
      std::max(kGraspableReach, family == "grip" ? 0.0 : half_depth_m - kSettle);
  if (gap < kSupportClearance && approach.z() < -kDownward && back < max_back) {
    back = std::min(back + (kSupportClearance - gap) / -approach.z(), max_back);
  }
  p.support_gap_m = lowest - back * approach.z() - support_z;
  p.pose.position = centre - back * approach;
  // Turning about a parallel axis through the palm frame moves the hand off the grasp by the
  // frame's distance from the axis times the turn: keep that under a centimetre.
  const double off_axis = back * approach.cross(free_axis).norm();
  p.free_turn_rad = off_axis > 1e-6 ? std::min(free_turn_rad, 0.01 / off_axis) : free_turn_rad;
  return p;
}

std::optional<Handle> tool_handle(const core::PerceivedObject& object) {
  const auto grip = object.frames.find("grip");
  if (grip == object.frames.end()) return std::nullopt;
  Handle h;
  h.centre = grip->second.position;
  h.shape = nearest_shape(Geometry(object).shapes(), h.centre);
  h.axis =
      h.shape.type == core::Shape::Type::kCapsule || h.shape.type == core::Shape::Type::kCylinder
          ? h.shape.pose.orientation * Eigen::Vector3d::UnitZ()
          : grip->second.orientation * Eigen::Vector3d::UnitX();
  h.axis.normalize();
  return h;
}

bool rings(const Handle& handle, const std::vector<Eigen::Vector3d>& points) {
  // Seen along the axis, the centre is inside the points' convex hull when no half-plane
  // through it holds them all: every angular gap between the points, round it, is under pi.
  const Eigen::Vector3d u = handle.axis.unitOrthogonal(), v = handle.axis.cross(u);
  std::vector<double> angles;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d d = p - handle.centre;
    if (std::hypot(d.dot(u), d.dot(v)) > 1e-6) angles.push_back(std::atan2(d.dot(v), d.dot(u)));
  }
  if (angles.size() < 3) return false;
  std::sort(angles.begin(), angles.end());
  double widest = angles.front() + 2 * M_PI - angles.back();
  for (size_t i = 1; i < angles.size(); ++i) widest = std::max(widest, angles[i] - angles[i - 1]);
  return widest < M_PI - kRingMarginRad;
}

std::vector<GraspCandidate> grasp_candidates(const core::PerceivedObject& object,
                                             const HandGeometry& hand,
                                             const Eigen::Vector3d& from) {
  std::vector<GraspCandidate> out;
  if (hand.fingers < 1 || hand.aperture_m <= 0) return out;
  const Geometry geometry(object);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d centre = geometry.centre();
  Eigen::Vector3d toward = horizontal(centre - from);
  // The object's own horizontal axes: of its frame's axes, the two least vertical.
  const Eigen::Matrix3d r = object.pose.orientation.toRotationMatrix();
  int up_axis = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(r(2, i)) > std::abs(r(2, up_axis))) up_axis = i;
  }
  Eigen::Vector3d ex = horizontal(r.col((up_axis + 1) % 3));
  if (ex.isZero()) ex = horizontal(r.col((up_axis + 2) % 3));
  if (ex.isZero()) ex = Eigen::Vector3d::UnitX();
  if (toward.isZero()) toward = ex;
  const Eigen::Vector3d ey = up.cross(ex);
  const bool round = geometry.round();
  // How far a hand closing along horizontal `closing` may turn about the vertical.
  auto turn_about_vertical = [&](const Eigen::Vector3d& closing) {
    return round ? M_PI / 8 : free_turn(geometry.shapes(), closing, hand.aperture_m);
  };
  const double bottom = geometry.extent(up).first, top = geometry.extent(up).second;
  std::map<std::string, int> counts;
  // `length`: the grasped section's length along the axis across the hand (approach x
  // closing), centred on `at`.
  auto add = [&](const std::string& family, Eigen::Vector3d at, const Eigen::Vector3d& approach,
                 const Eigen::Vector3d& closing, double width, double half_depth,
                 const Eigen::Vector3d& free_axis, double turn, double cost, bool fallback,
                 double length) {
    // Wider than the fingers' roots spread, the fingers must pass round it and close on it
    // (tried only after every grasp between the roots found no way there).
    const bool spans = width <= hand.aperture_m;
    GraspCandidate c;
    c.family = family;
    c.centre = at;
    c.approach = approach.normalized();
    c.closing = closing.normalized();
    c.width_m = width;
    c.half_depth_m = half_depth;
    c.support_z = bottom;
    if (turn > 0) {
      c.free_axis = free_axis.normalized();
      c.free_turn_rad = turn;
    }
    if (!spans) {
      c.wrap_length_m = length;
      if (!c.wrapped_at(hand, kWrapClearance)) return;  // nor wrap it
    }
    // Wrapped grasps are numbered on their own: the others' ids stay as they were.
    const std::string key = spans ? family : family + ".w";
    c.id = key + (spans ? "." : "") + std::to_string(counts[key]++);
    c.score = cost + (width > kLooseFit * hand.aperture_m ? 10.0 : 0.0);
    c.fallback = fallback || !spans;
    // A hand coming down whose fingers would reach the support even held back: the last resort.
    if (c.approach.z() < -kDownward && c.place(hand, 0).support_gap_m < 0) c.score += 20.0;
    out.push_back(c);
  };

  // A tool: the fingers wrap its handle, across the handle's axis, from above first.
  if (const std::optional<Handle> tool = tool_handle(object)) {
    const Eigen::Vector3d g = tool->centre, axis = tool->axis;
    const core::Shape& handle = tool->shape;
    Eigen::Vector3d down = -up - (-up).dot(axis) * axis;
    if (down.norm() < 1e-6) down = toward - toward.dot(axis) * axis;
    down.normalize();
    const Eigen::Vector3d aside =
        axis.cross(down).dot(toward) >= 0 ? axis.cross(down) : down.cross(axis);
    for (double phi : {0.0, 0.5, -0.5, 1.0, -1.0, M_PI / 2, -M_PI / 2}) {
      const Eigen::Vector3d a = std::cos(phi) * down + std::sin(phi) * aside;
      const Eigen::Vector3d closing = a.cross(axis).normalized();
      const double width = 2 * handle.half_width(closing);
      for (double sign : {1.0, -1.0}) {
        // The hand may turn all round the handle (IK keeps it off the rest of the tool).
        add("grip", g, a, sign * closing, width, handle.half_width(a), axis, M_PI,
            0.1 * std::abs(phi), false, 2 * handle.half_width(axis));
      }
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.score < b.score; });
    return out;
  }

  // From above: the palm stays over the top; the fingers close along the object's axes.
  {
    std::vector<Eigen::Vector3d> closings;
    if (round) {
      for (double yaw : {M_PI / 2, 0.0, M_PI / 4, -M_PI / 4})
        closings.push_back(yawed(toward, yaw));
    } else {
      closings = {ey, ex};
    }
    for (const Eigen::Vector3d& closing : closings) {
      for (double sign : {1.0, -1.0}) {
        const double turn = turn_about_vertical(closing);
        add("top", centre, -up, sign * closing, geometry.width(closing), top - centre.z(), up, turn,
            0.3, false, geometry.width(up.cross(closing)));
      }
    }
  }

  // From the side, towards the faces (or all round), closing horizontally then vertically.
  std::vector<Eigen::Vector3d> approaches;
  if (round) {
    for (double yaw :
         {0.0, M_PI / 4, -M_PI / 4, M_PI / 2, -M_PI / 2, 3 * M_PI / 4, -3 * M_PI / 4, M_PI}) {
      approaches.push_back(yawed(toward, yaw));
    }
  } else {
    approaches = {ex, -ex, ey, -ey};
    std::stable_sort(approaches.begin(), approaches.end(),
                     [&](const auto& a, const auto& b) { return a.dot(toward) > b.dot(toward); });
  }
  for (int vertical = 0; vertical < 2; ++vertical) {
    for (const Eigen::Vector3d& a : approaches) {
      const Eigen::Vector3d closing = vertical ? up : Eigen::Vector3d(up.cross(a).normalized());
      const double turn = vertical ? 0.0 : turn_about_vertical(closing);
      const double cost = angle_between(a, toward) / M_PI + (vertical ? 0.6 : 0.0);
      for (double sign : {1.0, -1.0}) {
        add("side", centre, a, sign * closing, geometry.width(closing), geometry.width(a) / 2, up,
            turn, cost, false, vertical ? geometry.width(up.cross(a)) : top - bottom);
      }
    }
  }
  // A part that sticks out sideways beyond the rest of the object (a mug's handle), grasped on
  // its own from outside, towards the object's middle: for a hand too small for the whole.
  for (const size_t i : core::protruding_shapes(object)) {
    const core::Shape& part = object.shapes[i];
    const Eigen::Vector3d out_dir = horizontal(part.pose.position - centre);
    // Straight in, or obliquely from either side.
    for (double yaw : {0.0, kPartObliqueRad, -kPartObliqueRad}) {
      const Eigen::Vector3d a = yawed(-out_dir, yaw);
      const Eigen::Vector3d closing = up.cross(a).normalized();
      const double turn = free_turn({part}, closing, hand.aperture_m);
      const double cost = kPartCost + angle_between(a, toward) / M_PI + std::abs(yaw);
      for (double sign : {1.0, -1.0}) {
        add("part", part.pose.position, a, sign * closing, 2 * part.half_width(closing),
            part.half_width(a), up, turn, cost, true, 2 * part.half_width(up));
      }
    }
  }

  // The same horizontal side grasps a little higher up the object: where the hand's own body
  // below the palm (a wide wrist) meets the surface the object stands on.
  if (kRaiseM <= kMaxRaiseShare * (top - centre.z()) + 1e-6) {
    for (const Eigen::Vector3d& a : approaches) {
      const Eigen::Vector3d closing = up.cross(a).normalized();
      const double turn = turn_about_vertical(closing);
      const double cost = kRaisedCost + angle_between(a, toward) / M_PI;
      for (double sign : {1.0, -1.0}) {
        add("side", centre + kRaiseM * up, a, sign * closing, geometry.width(closing),
            geometry.width(a) / 2, up, turn, cost, true,
            2 * std::min(top - centre.z() - kRaiseM, centre.z() + kRaiseM - bottom));
      }
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.score < b.score; });
  return out;
}

std::string reached_grasp_note(const std::string& object, const std::string& side) {
  return "grasp." + object + "." + side + ".reached";
}

std::string blocked_fingers_note(const std::string& object, const std::string& side) {
  return "grasp." + object + "." + side + ".blocked";
}

std::string failed_grasps_note(const std::string& object, const std::string& side) {
  return "grasp." + object + "." + side + ".failed";
}

}  // namespace taskmatrix::programs
