#include "taskmatrix/mujoco/robot_check.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "taskmatrix/mujoco/body_kinematics.h"
#include "taskmatrix/mujoco/kinematics.h"

namespace taskmatrix::mujoco {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Level = RobotFinding::Level;

constexpr double kMirrorTolM = 0.005;
constexpr double kMirrorTolRad = 3.0 * M_PI / 180.0;
constexpr double kNearLimit = 1e-3;
constexpr double kFingerCloses = 0.005;
// How often (s of the motion) the canned check samples a canned motion.
constexpr double kCannedSampleS = 0.02;

// The items with `sep` between them ("a, b, c").
template <class Strings>
std::string joined(const Strings& items, const char* sep) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : sep) + item;
  return out;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

Vec3 mirrored(const Vec3& v) { return {v.x(), -v.y(), v.z()}; }

// A uniform draw in [lo, hi] from the generator's bits (the same on every platform).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// One mjData of a scene with helpers for forward kinematics.
class Probe {
 public:
  explicit Probe(const Scene& scene) : scene_(scene), m_(scene.model()), d_(make_data(m_)) {}

  // The start pose (rest posture); with `at_origin` the base stands at the origin facing +x.
  void reset(bool at_origin) {
    std::copy(scene_.start_qpos().begin(), scene_.start_qpos().end(), d_->qpos);
    if (at_origin) {
      for (int adr : scene_.chain("base").qpos_adr) d_->qpos[adr] = 0;
    }
  }
  void set(const std::string& chain, const std::vector<double>& values) {
    const ChainIndex& c = scene_.chain(chain);
    for (size_t i = 0; i < c.qpos_adr.size() && i < values.size(); ++i) {
      d_->qpos[c.qpos_adr[i]] = values[i];
    }
  }
  void set_posture(const std::string& posture) { scene_.apply_posture(posture, d_->qpos); }
  void kinematics() {
    mj_kinematics(m_, d_.get());
    mj_camlight(m_, d_.get());
  }
  // Contacts (distance < 0) after kinematics: pairs of geoms at least one of which is the
  // robot's.
  std::vector<std::pair<int, int>> contacts() {
    mj_collision(m_, d_.get());
    std::vector<std::pair<int, int>> out;
    for (int i = 0; i < d_->ncon; ++i) {
      const mjContact& c = d_->contact[i];
      if (c.dist >= 0) continue;
      if (scene_.is_robot_geom(c.geom1) || scene_.is_robot_geom(c.geom2)) {
        out.push_back({c.geom1, c.geom2});
      }
    }
    return out;
  }

  Vec3 position(const std::string& frame) const {
    return frame_pose(d_.get(), scene_.frame(frame)).position;
  }
  Mat3 rotation(const std::string& frame) const {
    return frame_pose(d_.get(), scene_.frame(frame)).orientation.toRotationMatrix();
  }
  int frame_body(const std::string& frame) const {
    const FrameRef f = scene_.frame(frame);
    return f.kind == FrameRef::Kind::kSite   ? m_->site_bodyid[f.id]
           : f.kind == FrameRef::Kind::kBody ? f.id
                                             : m_->cam_bodyid[f.id];
  }
  // Where a finger ends: the centre of its last segment's geoms (the body's origin if it
  // has none).
  Vec3 segment_centre(int body) const {
    Vec3 sum = Vec3::Zero();
    int n = 0;
    for (int g = 0; g < m_->ngeom; ++g) {
      if (m_->geom_bodyid[g] != body) continue;
      sum += Vec3(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1], d_->geom_xpos[3 * g + 2]);
      ++n;
    }
    if (n > 0) return sum / n;
    return {d_->xpos[3 * body], d_->xpos[3 * body + 1], d_->xpos[3 * body + 2]};
  }
  // The furthest point of a geom along `dir` (unit), as dir . p.
  double support(int g, const Vec3& dir) const {
    const mjtNum u[3] = {dir.x(), dir.y(), dir.z()};
    return geom_support(m_, d_.get(), g, u);
  }

  Vec3 body_position(int body) const {
    return {d_->xpos[3 * body], d_->xpos[3 * body + 1], d_->xpos[3 * body + 2]};
  }
  const mjModel* model() const { return m_; }

 private:
  const Scene& scene_;
  const mjModel* m_;
  DataPtr d_;
};

bool is_descendant(const mjModel* m, int body, int ancestor) {
  for (int b = body; b > 0; b = m->body_parentid[b]) {
    if (b == ancestor) return true;
  }
  return false;
}

// Bodies that a joint of one of `chains` moves.
std::vector<char> moved_by(const Scene& scene, const std::vector<std::string>& chains) {
  const mjModel* m = scene.model();
  std::vector<char> moved(m->nbody, 0);
  for (const std::string& c : chains) {
    for (int j : scene.chain(c).joints) {
      for (int b = 0; b < m->nbody; ++b) moved[b] |= is_descendant(m, b, m->jnt_bodyid[j]);
    }
  }
  return moved;
}

std::string body_name(const mjModel* m, int body) {
  const char* n = mj_id2name(m, mjOBJ_BODY, body);
  return n ? n : "#" + std::to_string(body);
}

std::vector<double> clamped_zeros(const ChainIndex& c) {
  std::vector<double> q;
  for (size_t i = 0; i < c.lower.size(); ++i) q.push_back(std::clamp(0.0, c.lower[i], c.upper[i]));
  return q;
}

const std::vector<std::string> kLimbChains = {"left_arm", "right_arm", "left_hand", "right_hand"};

// The torso chain, or null for a robot with a rigid torso (the chain is optional).
const ChainIndex* torso_of(const Scene& scene) {
  return scene.robot().find_chain("torso") ? &scene.chain("torso") : nullptr;
}

RobotFinding check_chains(const Scene& scene) {
  const core::RobotProfile& robot = scene.robot();
  std::string dofs;
  for (const core::ChainSpec& c : robot.chains) {
    dofs += (dofs.empty() ? "" : ", ") + c.name + " " + std::to_string(c.joints.size());
  }
  for (const core::HandSpec& h : robot.hands) {
    dofs += "; " + h.side + " hand " + std::to_string(h.fingers.size()) + " fingers (";
    for (size_t f = 0; f < h.fingers.size(); ++f) {
      dofs += (f ? "+" : "") + std::to_string(h.fingers[f].joints.size());
    }
    dofs += " segments)";
  }
  std::string near;
  for (const auto& [posture_name, posture] : robot.postures) {
    for (const auto& [chain_name, values] : posture) {
      const ChainIndex& c = scene.chain(chain_name);
      for (size_t i = 0; i < values.size(); ++i) {
        const double gap = std::min(values[i] - c.lower[i], c.upper[i] - values[i]);
        if (gap < kNearLimit && near.size() < 200) {
          near += (near.empty() ? "" : ", ") + ("postures." + posture_name + "." + chain_name) +
                  " joint '" + mj_id2name(scene.model(), mjOBJ_JOINT, c.joints[i]) + "'";
        }
      }
    }
  }
  if (!near.empty()) {
    return {Level::kWarning, "chains",
            dofs +
                ". At a joint limit (a servo settles a hair past it; a program that "
                "commands the measured value then asks for more than the limit): " +
                near};
  }
  return {Level::kOk, "chains", dofs + "; every posture keeps 1e-3 from the joint limits"};
}

// Every canned motion as the canned program plays it (the chains it names through its
// keyframes, interpolated linearly, the rest of the robot at rest), sampled every
// kCannedSampleS: the first time one of the robot's links touches another of its links or
// the floor. A motion that does fails every trial that plays it (collision).
std::vector<RobotFinding> check_canned(const Scene& scene) {
  std::vector<RobotFinding> out;
  Probe probe(scene);
  const mjModel* m = scene.model();
  std::vector<std::string> clean;
  // The robot against itself or a plane (the floor); furniture depends on the room.
  auto counts = [&](int g) { return scene.is_robot_geom(g) || m->geom_type[g] == mjGEOM_PLANE; };
  for (const auto& [name, motion] : scene.robot().canned) {
    std::string found;
    const std::vector<core::CannedMotion::Keyframe>& keys = motion.keyframes;
    for (size_t k = 0; k + 1 < keys.size() && found.empty(); ++k) {
      const double span = keys[k + 1].time_s - keys[k].time_s;
      const int steps = std::max(1, static_cast<int>(std::ceil(span / kCannedSampleS)));
      for (int s = 0; s <= steps && found.empty(); ++s) {
        const double f = static_cast<double>(s) / steps;
        probe.reset(true);
        size_t at = 0;
        for (const std::string& chain : motion.chains) {
          std::vector<double> v(scene.chain(chain).qpos_adr.size());
          for (double& x : v) {
            x = keys[k].values[at] + f * (keys[k + 1].values[at] - keys[k].values[at]);
            ++at;
          }
          probe.set(chain, v);
        }
        probe.kinematics();
        for (const auto& [g1, g2] : probe.contacts()) {
          if (!counts(g1) || !counts(g2)) continue;
          found = "canned." + name + ": at " + fixed(keys[k].time_s + f * span, 2) + " s " +
                  body_name(m, m->geom_bodyid[g1]) + " touches " + body_name(m, m->geom_bodyid[g2]);
          break;
        }
      }
    }
    if (!found.empty()) {
      out.push_back({Level::kError, "canned", found + " (canned and greet would collide)"});
    } else {
      clean.push_back(name);
    }
  }
  if (!clean.empty()) {
    out.push_back({Level::kOk, "canned",
                   joined(clean, ", ") +
                       ": the robot touches neither itself nor the floor through the keyframes"});
  }
  return out;
}

// Each joint of the torso, head and arms at each of its limits, the rest of the robot at rest:
// where two links of that joint's own chain then touch (an elbow folding the forearm into the
// upper arm), the range reaches past where the links meet (a real joint's mechanical stop
// comes first). IK and plans keep the links apart without a margin, so a goal may end a hair
// from that contact and physics then holds the links in it (a `collision`): a warning. A limb
// swung against the trunk (an arm adducted into the hip) is a posture, not a fold, and is not
// reported.
RobotFinding check_joint_ranges(const Scene& scene) {
  Probe probe(scene);
  const mjModel* m = scene.model();
  std::vector<std::string> found;
  int count = 0;
  for (const core::ChainSpec& spec : scene.robot().chains) {
    if (spec.name == "base" || spec.name == "left_hand" || spec.name == "right_hand") continue;
    const ChainIndex& c = scene.chain(spec.name);
    const std::vector<char> in_chain = moved_by(scene, {spec.name});
    for (size_t i = 0; i < c.joints.size(); ++i) {
      for (const bool upper : {false, true}) {
        probe.reset(true);
        const double v = upper ? c.upper[i] : c.lower[i];
        std::vector<double> q(c.joints.size());
        for (size_t k = 0; k < q.size(); ++k) {
          q[k] = scene.start_qpos()[static_cast<size_t>(c.qpos_adr[k])];
        }
        q[i] = v;
        probe.set(spec.name, q);
        probe.kinematics();
        for (const auto& [g1, g2] : probe.contacts()) {
          const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
          if (!in_chain[b1] || !in_chain[b2] || scene.same_hand(b1, b2)) continue;
          ++count;
          if (found.size() < 3) {
            found.push_back(spec.name + " joint '" + mj_id2name(m, mjOBJ_JOINT, c.joints[i]) +
                            "' at its " + (upper ? "upper" : "lower") + " limit " + fixed(v, 2) +
                            ": " + body_name(m, b1) + " touches " + body_name(m, b2));
          }
          break;
        }
      }
    }
  }
  if (found.empty()) {
    return {Level::kOk, "joint ranges",
            "every torso, head and arm joint at either limit (the rest at rest) leaves its "
            "chain's links apart"};
  }
  return {Level::kWarning, "joint ranges",
          std::to_string(count) +
              " joint limits fold a link of the chain into another (the range reaches past "
              "where they meet; a plan may end a hair from that contact and physics then holds "
              "it): " +
              joined(found, "; ")};
}

std::vector<RobotFinding> check_postures(const Scene& scene) {
  std::vector<RobotFinding> out;
  Probe probe(scene);
  const mjModel* m = scene.model();
  std::vector<std::string> clean;
  for (const auto& [name, posture] : scene.robot().postures) {
    probe.reset(false);
    probe.set_posture(name);
    probe.kinematics();
    std::vector<char> hand_bodies;
    if (name == "fist") {
      hand_bodies = moved_by(scene, {"left_hand", "right_hand"});
      for (const core::HandSpec& h : scene.robot().hands) hand_bodies[probe.frame_body(h.palm)] = 1;
    }
    std::set<std::string> touching, within_hand;
    for (const auto& [g1, g2] : probe.contacts()) {
      const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
      const std::string pair = body_name(m, b1) + " touches " + body_name(m, b2);
      if (!hand_bodies.empty() && hand_bodies[b1] && hand_bodies[b2]) {
        within_hand.insert(pair);
      } else {
        touching.insert(pair);
      }
    }
    if (!touching.empty()) {
      out.push_back({Level::kError, "postures",
                     "postures." + name + ": at the start of " + scene.environment().name + ", " +
                         joined(touching, "; ")});
    } else if (!within_hand.empty()) {
      out.push_back({Level::kWarning, "postures",
                     "postures.fist: fingers touch each other or the palm (" +
                         *within_hand.begin() +
                         "): grasp stops a segment that touches anything, so the hand may "
                         "close short of the object"});
    } else {
      clean.push_back(name);
    }
  }
  if (!clean.empty()) {
    out.push_back(
        {Level::kOk, "postures",
         joined(clean, ", ") + ": touch nothing at the start of " + scene.environment().name});
  }
  return out;
}

RobotFinding check_camera(const Scene& scene) {
  Probe probe(scene);
  probe.reset(true);
  probe.kinematics();
  const std::string& cam = scene.robot().head_camera.name;
  const Vec3 ahead = -probe.rotation(cam).col(2);
  const double below = std::atan2(-ahead.z(), std::hypot(ahead.x(), ahead.y())) * 180 / M_PI;
  const double fovy = scene.model()->cam_fovy[scene.head_camera()];
  return {Level::kOk, "head camera",
          "'" + cam + "' at " + fixed(probe.position(cam).z(), 2) + " m looks forward, " +
              fixed(below, 0) + " degrees below the horizontal at rest, upright, vertical field " +
              fixed(fovy, 0) + " degrees; " +
              (scene.robot().find_chain("head") ? "the head chain moves it"
                                                : "fixed to the trunk (no head chain): the "
                                                  "base's yaw aims it")};
}

struct HandProbe {
  const core::HandSpec* hand = nullptr;
  std::vector<Vec3> tips_rest, tips_fist;  // world, base at the origin
  Vec3 palm = Vec3::Zero();
  Mat3 palm_rotation = Mat3::Identity();
};

// Fingertips of `hand` at rest and in fist, with the arms at `arm_left` / `arm_right` if
// given (else at rest) and the hands at the given values (else rest / fist).
void probe_tips(Probe& probe, const Scene& scene, HandProbe& h) {
  probe.reset(true);
  probe.kinematics();
  h.palm = probe.position(h.hand->palm);
  h.palm_rotation = probe.rotation(h.hand->palm);
  const mjModel* m = probe.model();
  auto tips = [&]() {
    std::vector<Vec3> out;
    for (const core::FingerSpec& f : h.hand->fingers) {
      out.push_back(probe.segment_centre(mj_name2id(m, mjOBJ_BODY, f.bodies.back().c_str())));
    }
    return out;
  };
  h.tips_rest = tips();
  const std::string chain = h.hand->side + "_hand";
  probe.set(chain, scene.robot().postures.at("fist").at(chain));
  probe.kinematics();
  h.tips_fist = tips();
}

std::vector<RobotFinding> check_hands(const Scene& scene) {
  std::vector<RobotFinding> out;
  Probe probe(scene);
  const mjModel* m = scene.model();
  for (const core::HandSpec& hand : scene.robot().hands) {
    HandProbe h;
    h.hand = &hand;
    probe_tips(probe, scene, h);
    const std::string key = "hands." + hand.side;
    const Vec3 approach =
        h.palm_rotation * Vec3(hand.approach[0], hand.approach[1], hand.approach[2]);
    const Vec3 closing = h.palm_rotation * Vec3(hand.closing[0], hand.closing[1], hand.closing[2]);
    const Vec3 across = approach.cross(closing);
    // Palm geometry stays behind the palm origin along approach.
    probe.reset(true);
    probe.kinematics();
    const int palm_body = probe.frame_body(hand.palm);
    double reach = -1e9;
    int front_geom = -1;
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] != palm_body || !(m->geom_contype[g] || m->geom_conaffinity[g]))
        continue;
      const double s = probe.support(g, approach) - approach.dot(h.palm);
      if (s > reach) {
        reach = s;
        front_geom = g;
      }
    }
    if (front_geom >= 0 && reach > 0) {
      const char* gname = mj_id2name(m, mjOBJ_GEOM, front_geom);
      out.push_back({Level::kError, "palm axes",
                     key + ".approach: geom '" + std::string(gname ? gname : "?") +
                         "' of the palm's body reaches " + fixed(reach * 100, 1) +
                         " cm past the palm origin along approach (reach brings the object's "
                         "centre to the palm origin along approach: approach must point out of "
                         "the palm, towards where the fingers close)"});
      continue;
    }
    std::string bad_closing, bad_closer;
    double worst_closer = 1e9;
    int along = 0;  // fingers whose tips close more along `closing` than across it
    for (size_t f = 0; f < hand.fingers.size(); ++f) {
      const Vec3 d = h.tips_fist[f] - h.tips_rest[f];
      if (std::abs(d.dot(closing)) >= std::abs(d.dot(across))) {
        ++along;
      } else if (bad_closing.empty()) {
        bad_closing = "fingers[" + std::to_string(f) + "] moves " + fixed(d.dot(across) * 100, 1) +
                      " cm across the closing axis and " + fixed(d.dot(closing) * 100, 1) +
                      " cm along it";
      }
      const double closer = (h.tips_rest[f] - h.palm).norm() - (h.tips_fist[f] - h.palm).norm();
      worst_closer = std::min(worst_closer, closer);
      if (closer < kFingerCloses && bad_closer.empty()) {
        bad_closer = "fingers[" + std::to_string(f) + "]: its tip ends " + fixed(-closer * 100, 1) +
                     " cm further from the palm origin in fist than at rest";
      }
    }
    const int needed = std::min<int>(2, static_cast<int>(hand.fingers.size()));
    if (along < needed) {
      out.push_back({Level::kError, "palm axes",
                     key + ".closing: from rest to fist " + bad_closing + "; " +
                         std::to_string(along) + " of " + std::to_string(hand.fingers.size()) +
                         " fingers close along it, grasp needs " + std::to_string(needed) +
                         " on the object (reach keeps the closing axis horizontal for upright "
                         "objects)"});
    } else if (!bad_closing.empty()) {
      out.push_back({Level::kWarning, "palm axes",
                     key + ".closing: from rest to fist " + bad_closing + " (" +
                         std::to_string(along) + " of " + std::to_string(hand.fingers.size()) +
                         " fingers close along it: with the closing axis horizontal around an "
                         "upright object, that finger closes above or below it)"});
    } else {
      out.push_back({Level::kOk, "palm axes",
                     key + ": the palm stays " + fixed(-reach * 100, 1) +
                         " cm behind its origin along approach; the fingers close along closing"});
    }
    if (!bad_closer.empty()) {
      out.push_back({Level::kError, "fingers",
                     key + ".fingers: " + bad_closer +
                         " (grasp closes every segment from where it is towards fist)"});
    } else {
      out.push_back({Level::kOk, "fingers",
                     key + ": every fingertip closes at least " + fixed(worst_closer * 100, 1) +
                         " cm towards the palm origin from rest to fist"});
    }
  }
  return out;
}

std::vector<RobotFinding> check_mirror(const Scene& scene) {
  const core::RobotProfile& robot = scene.robot();
  const ChainIndex& left = scene.chain("left_arm");
  const ChainIndex& right = scene.chain("right_arm");
  const ChainIndex* torso = torso_of(scene);
  const std::vector<double>& signs = robot.mirror_signs.at("arm");
  const core::HandSpec* lh = robot.find_hand("left");
  const core::HandSpec* rh = robot.find_hand("right");
  const Vec3 la(lh->approach[0], lh->approach[1], lh->approach[2]);
  const Vec3 ra(rh->approach[0], rh->approach[1], rh->approach[2]);
  Probe probe(scene);
  std::mt19937_64 rng(20261201);
  double worst_m = 0, worst_rad = 0;
  std::vector<double> worst_q;
  int samples = 0;
  for (int draw = 0; draw < 2000 && samples < 100; ++draw) {
    std::vector<double> ql, qr;
    bool inside = true;
    for (size_t i = 0; i < left.lower.size(); ++i) {
      ql.push_back(uniform(rng, left.lower[i], left.upper[i]));
      qr.push_back(signs[i] * ql.back());
      inside = inside && qr[i] >= right.lower[i] && qr[i] <= right.upper[i];
    }
    if (!inside) continue;
    ++samples;
    probe.reset(true);
    if (torso) probe.set("torso", clamped_zeros(*torso));
    probe.set("left_arm", ql);
    probe.set("right_arm", qr);
    probe.kinematics();
    const double dm = (probe.position(rh->palm) - mirrored(probe.position(lh->palm))).norm();
    const Vec3 al = mirrored(probe.rotation(lh->palm) * la);
    const Vec3 ar = probe.rotation(rh->palm) * ra;
    const double drad = std::acos(std::clamp(al.dot(ar), -1.0, 1.0));
    if (dm > worst_m || drad > worst_rad) {
      worst_m = std::max(worst_m, dm);
      worst_rad = std::max(worst_rad, drad);
      worst_q = ql;
    }
  }
  if (samples == 0) {
    return {{Level::kError, "mirror signs",
             "mirror_signs.arm: no left-arm configuration mirrors into the right arm's limits"}};
  }
  if (worst_m > kMirrorTolM || worst_rad > kMirrorTolRad) {
    std::string q;
    for (double v : worst_q) q += (q.empty() ? "" : ", ") + fixed(v, 2);
    return {{Level::kError, "mirror signs",
             "mirror_signs.arm: at left_arm [" + q + "] and its mirror image the right palm is " +
                 fixed(worst_m * 100, 1) + " cm and " + fixed(worst_rad * 180 / M_PI, 1) +
                 " degrees (approach) from the mirror image of the left palm (postural, canned "
                 "and greet mirror one side's postures and motions with these signs)"}};
  }
  std::vector<RobotFinding> out{
      {Level::kOk, "mirror signs",
       "arm: " + std::to_string(samples) + " mirrored configurations put the palms within " +
           fixed(worst_m * 1000, 2) + " mm and " + fixed(worst_rad * 180 / M_PI, 2) +
           " degrees of mirror images"}};
  // Hands: the fist of the left hand and its mirror image on the right, both arms mirrored.
  const std::vector<double>& hand_signs = robot.mirror_signs.at("hand");
  const auto& fist = robot.postures.at("fist");
  std::vector<double> rest_left = scene.robot().postures.at("rest").at("left_arm"), rest_mirror;
  for (size_t i = 0; i < rest_left.size(); ++i) rest_mirror.push_back(signs[i] * rest_left[i]);
  std::vector<double> fist_mirror;
  for (size_t i = 0; i < fist.at("left_hand").size(); ++i) {
    fist_mirror.push_back(hand_signs[i] * fist.at("left_hand")[i]);
  }
  probe.reset(true);
  if (torso) probe.set("torso", clamped_zeros(*torso));
  probe.set("left_arm", rest_left);
  probe.set("right_arm", rest_mirror);
  probe.set("left_hand", fist.at("left_hand"));
  probe.set("right_hand", fist_mirror);
  probe.kinematics();
  const mjModel* m = scene.model();
  double worst_tip = 0;
  for (const core::FingerSpec& f : lh->fingers) {
    const Vec3 tip =
        mirrored(probe.segment_centre(mj_name2id(m, mjOBJ_BODY, f.bodies.back().c_str())));
    double nearest = 1e9;
    for (const core::FingerSpec& g : rh->fingers) {
      nearest = std::min(
          nearest,
          (probe.segment_centre(mj_name2id(m, mjOBJ_BODY, g.bodies.back().c_str())) - tip).norm());
    }
    worst_tip = std::max(worst_tip, nearest);
  }
  if (worst_tip > kMirrorTolM) {
    out.push_back({Level::kError, "mirror signs",
                   "mirror_signs.hand: the left fist mirrored to the right hand puts a right "
                   "fingertip " +
                       fixed(worst_tip * 100, 1) + " cm from the mirror image of the left one"});
  } else {
    out.push_back({Level::kOk, "mirror signs",
                   "hand: the mirrored fist's fingertips lie within " + fixed(worst_tip * 1000, 2) +
                       " mm of mirror images"});
  }
  return out;
}

}  // namespace

std::vector<RobotFinding> check_robot_kinematics(const Scene& scene) {
  std::vector<RobotFinding> out;
  out.push_back(check_chains(scene));
  for (RobotFinding& f : check_postures(scene)) out.push_back(std::move(f));
  for (RobotFinding& f : check_canned(scene)) out.push_back(std::move(f));
  out.push_back(check_joint_ranges(scene));
  out.push_back(check_camera(scene));
  for (RobotFinding& f : check_mirror(scene)) out.push_back(std::move(f));
  for (RobotFinding& f : check_hands(scene)) out.push_back(std::move(f));
  return out;
}

namespace {
// The solid surfaces of the heights check: tops from, to and every, in cm.
constexpr int kHeightsFromCm = 40, kHeightsToCm = 100, kHeightsStepCm = 5;
// A palm that grasps: its approach axis within 30 degrees of the horizontal, or of down (and,
// for grasps of upright objects, its closing axis within 30 degrees of the horizontal).
const double kGraspTiltSin = std::sin(M_PI / 6), kGraspDownCos = std::cos(M_PI / 6);
}  // namespace

std::vector<RobotFinding> check_reach_envelope(
    const std::vector<std::shared_ptr<const Scene>>& scenes, double min_reach_m) {
  std::vector<RobotFinding> out;
  if (scenes.empty()) return out;
  const Scene& scene = *scenes.front();
  const mjModel* m = scene.model();
  Probe probe(scene);
  probe.reset(true);
  probe.kinematics();

  // The surfaces, and the robot's front at each surface: the furthest forward of its geoms
  // that no limb moves and that reach below the surface's top (the surface is taken as solid
  // down to the floor, as a counter is; what is higher passes over it).
  // `best`: how far beyond the front the palm gets with the fingers closing as a grasp of an
  // upright object closes them; `best_any`: with the approach alone (a tool's grip closes
  // across its handle, in any direction).
  struct Surface {
    std::string label;
    double top = 0, front = 0, best = -1e9, best_any = -1e9;
    Vec3 palm = Vec3::Zero();
  };
  std::vector<Surface> surfaces;
  const std::vector<char> limbs = moved_by(scene, kLimbChains);
  auto front_at = [&](double top) {
    double front = -1e9;
    for (int g = 0; g < m->ngeom; ++g) {
      if (!scene.is_robot_geom(g) || limbs[m->geom_bodyid[g]]) continue;
      if (!(m->geom_contype[g] || m->geom_conaffinity[g])) continue;
      if (-probe.support(g, -Vec3::UnitZ()) >= top) continue;  // passes over the surface
      front = std::max(front, probe.support(g, Vec3::UnitX()));
    }
    return front;
  };
  for (const auto& s : scenes) {
    Probe env(*s);
    env.reset(true);
    env.kinematics();
    const mjModel* em = s->model();
    for (const auto& [name, obj] : s->environment().objects) {
      if (obj.kind != core::ObjectKind::kSurface) continue;
      // A surface's body origin is the centre of its top face (models/README.md).
      const int b = mj_name2id(em, mjOBJ_BODY, obj.bodies.front().c_str());
      const double top = env.body_position(b).z();
      Surface surface;
      surface.label = s->environment().name + " " + name;
      surface.top = top;
      surface.front = front_at(top);
      surfaces.push_back(surface);
    }
  }
  // Solid surfaces of every height in a range: which heights the robot serves, how far in.
  const size_t named = surfaces.size();
  for (int cm = kHeightsFromCm; cm <= kHeightsToCm; cm += kHeightsStepCm) {
    Surface surface;
    surface.label = std::to_string(cm);
    surface.top = cm / 100.0;
    surface.front = front_at(surface.top);
    surfaces.push_back(surface);
  }

  std::mt19937_64 rng(20261202);
  const ChainIndex* torso = torso_of(scene);
  for (const core::HandSpec& hand : scene.robot().hands) {
    const ChainIndex& arm = scene.chain(hand.side + "_arm");
    for (int n = 0; n < 4000; ++n) {
      std::vector<double> qa, qt;
      for (size_t i = 0; i < arm.lower.size(); ++i)
        qa.push_back(uniform(rng, arm.lower[i], arm.upper[i]));
      for (size_t i = 0; torso && i < torso->lower.size(); ++i) {
        qt.push_back(uniform(rng, torso->lower[i], torso->upper[i]));
      }
      probe.reset(true);
      probe.set(hand.side + "_arm", qa);
      if (torso) probe.set("torso", qt);
      probe.kinematics();
      const Vec3 p = probe.position(hand.palm);
      if (std::abs(p.y()) > 0.35) continue;
      // With the hand as a grasp holds it: approaching within 30 degrees of the horizontal
      // (round an object) or of straight down (from above).
      const Vec3 approach =
          probe.rotation(hand.palm) * Vec3(hand.approach[0], hand.approach[1], hand.approach[2]);
      const double down = -approach.normalized().z();
      if (!(std::abs(down) <= kGraspTiltSin || down >= kGraspDownCos)) continue;
      // With the fingers closing within 30 degrees of the horizontal too, as the top and side
      // grasps of an upright object close them (all but the vertical closings, ranked last:
      // taskmatrix/programs/grasp_candidates.h).
      const Vec3 closing =
          probe.rotation(hand.palm) * Vec3(hand.closing[0], hand.closing[1], hand.closing[2]);
      const bool level = std::abs(closing.normalized().z()) <= kGraspTiltSin;
      int collides = -1;  // unknown
      for (Surface& s : surfaces) {
        if (p.z() < s.top + 0.02 || p.z() > s.top + 0.15) continue;
        const double beyond = p.x() - s.front;
        const bool better_any = beyond > s.best_any, better = level && beyond > s.best;
        if (!better_any && !better) continue;
        if (collides < 0) {
          collides = 0;
          for (const auto& [g1, g2] : probe.contacts()) {
            collides |= scene.is_robot_geom(g1) && scene.is_robot_geom(g2);
          }
        }
        if (collides) break;
        if (better_any) s.best_any = beyond;
        if (better) {
          s.best = beyond;
          s.palm = p;
        }
      }
    }
  }
  // A best distance as shown: metres, or "nowhere" where no sample got over the surface.
  auto shown = [](double best, const char* unit) {
    return best < -1e8 ? std::string("nowhere") : fixed(best, 2) + unit;
  };
  // How far beyond the front the palm gets over a surface of each height.
  std::string reaches;
  bool any = false;
  for (size_t k = named; k < surfaces.size(); ++k) {
    const Surface& s = surfaces[k];
    any = any || s.best >= min_reach_m;
    reaches += (reaches.empty() ? "" : ", ") + fixed(s.top, 2) + ": " + shown(s.best, "");
  }
  out.push_back({any ? Level::kOk : Level::kWarning, "surface heights",
                 "how far (m) the palm, as a grasp of an upright object holds it, gets beyond the "
                 "robot's front 2-15 cm above a solid surface of each top height (m): " +
                     reaches});
  surfaces.resize(named);
  for (const Surface& s : surfaces) {
    const std::string where = s.label + " (top " + fixed(s.top, 3) + " m, the robot's front at x " +
                              fixed(s.front, 2) + " m)";
    if (s.best_any < min_reach_m) {
      out.push_back({Level::kError, "reach envelope",
                     where + ": the palm gets " + shown(s.best_any, " m") +
                         " beyond the robot's front 2-15 cm above the top (need " +
                         fixed(min_reach_m, 2) +
                         " m: objects stand up to that far in from an edge)"});
    } else if (s.best < min_reach_m) {
      out.push_back({Level::kWarning, "reach envelope",
                     where + ": the palm gets " + shown(s.best_any, " m") +
                         " beyond the robot's front 2-15 cm above the top, but with its fingers "
                         "closing within 30 degrees of the horizontal, as grasps of upright "
                         "objects close them, " +
                         shown(s.best, " m") + " (need " + fixed(min_reach_m, 2) +
                         " m): cups and boxes there are out of reach, a tool's grip may not be"});
    } else {
      out.push_back({Level::kOk, "reach envelope",
                     where + ": the palm gets " + fixed(s.best, 2) +
                         " m beyond the front, at height " + fixed(s.palm.z(), 2) + " m"});
    }
  }
  return out;
}

}  // namespace taskmatrix::mujoco
