// Grasps of an object, generated from its geometry and ranked for one hand. Robot-independent:
// the hand is measured through the skillset (forward kinematics of the profile's palm frame and
// finger bodies), the object comes from the perceptual model (its collision shapes, a tool's
// grip frame).
//
// Candidates, each a palm frame placement with the hand's approach and closing axes in the
// world:
//   grip  a tool's grip frame: the fingers wrap the handle (the shape at the grip point),
//         approaching across the handle's axis, from above first;
//   top   from above, closing along the object's horizontal axes (or several directions
//         for an object that is round about the vertical); the palm stays above the top;
//   side  horizontally, towards the object's faces (or from several directions around a round
//         object), closing horizontally across it, then closing vertically; and last the
//         horizontal closings again 2 cm higher up the object (where a wide wrist below the
//         palm meets the surface under a short object), if that stays within the middle half
//         of its height;
//   part  for an object of several shapes, a shape that sticks out sideways beyond the rest
//         (a mug's handle) on its own: horizontally from outside towards the object's middle,
//         straight or 0.6 rad from either side, closing across the part.
// Each has the width along its closing axis (of the object, or of the part). A candidate the
// hand cannot span (width over the aperture of its fingers) is left out unless the fingers
// close round it all the same (HandGeometry::wraps), and then it is a `fallback`; the rest are
// ranked:
// those that fit loosely before tight ones, then by how directly the hand comes in from where
// it is (a side approach pointing away from the robot is the easiest), top grasps between the
// direct and the oblique side approaches, vertical closings last, and after all of them those
// coming down whose fingers would reach the surface the object stands on. The parts, the
// raised side grasps and the wrapped ones are `fallback`: reach tries them in a second round,
// only when it found no way to any of the others (or there are no others). Ids name the family
// and index and stay the same while the object and the robot's side of it do, so a grasp that
// failed can be left out of the next attempt.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/skillset.h"

namespace taskmatrix::programs {

// What a hand can hold, measured at its `hand_open` posture (or `rest`).
struct HandGeometry {
  std::string side;
  Eigen::Vector3d approach = Eigen::Vector3d::UnitZ();  // palm frame, from the profile
  Eigen::Vector3d closing = Eigen::Vector3d::UnitX();   // palm frame, from the profile
  // Spread of the fingers' first joints along the closing axis: the widest object the
  // fingers close around with the object between their roots.
  double aperture_m = 0;
  // How far behind the palm frame (against the approach axis) the fingers' first joints sit:
  // about where the palm is. For a finger whose first segment slides (a parallel jaw), where
  // the palm's geometry ends instead (Skillset::palm_depth).
  double palm_depth_m = 0;
  // How far ahead of the palm frame (along the approach axis) the fingers' last segments begin
  // when the hand is closed (`fist`): a section grasped nearer the palm than this lies behind
  // the closed fingertips, out of their reach, unless the fingers curl back to the palm.
  double closed_reach_m = 0;
  // Points of the open fingers in the palm frame: their segments' origins and an estimate of
  // each fingertip (the last segment as long as the one before it, straight on).
  std::vector<Eigen::Vector3d> finger_points;
  // The same points of each finger (segments' origins, then the fingertip estimate carried by
  // the last segment) in the palm frame at each step of the closing from open to `fist`,
  // every finger joint turning at the same speed, as grasp closes them: sweeps[finger][step].
  std::vector<std::vector<std::vector<Eigen::Vector3d>>> sweeps;
  // Whether the fingers wrap a section of the object `width` wide along the closing axis and
  // `length` long along the axis across the hand (approach x closing), its middle `ahead` of
  // the palm frame along the approach, taken as a round bar of that width: the open fingers
  // (sweeps' first step) keep out of it and, closing, a majority of them meet it, on both
  // sides of its middle along the closing axis, one of them past its middle along the
  // approach (else the fingers push it out of the hand). An estimate from the fingers'
  // points, which leaves out their thickness and a flat side's corners: it only admits a
  // grasp, and grasp counts the fingers that really touch. How a hand holds an object wider
  // than the spread of its fingers' roots (a human hand round a mug: the fingers curl round
  // from beside the palm).
  bool wraps(double width, double length, double ahead) const;
  // The points the fingers pass through while closing on a bar of `radius` round the line
  // through `centre` along `axis` (palm frame): each finger's sweep up to the first step at
  // which it comes within `radius` of the line, where it stops; radius 0: the whole sweep.
  std::vector<Eigen::Vector3d> swept_points(const Eigen::Vector3d& centre,
                                            const Eigen::Vector3d& axis, double radius) const;
  // Each finger's fingertip estimate in its last segment's frame (zero for a one-segment
  // finger: its frame's origin).
  std::vector<Eigen::Vector3d> tips_in_last;
  int fingers = 0;
  // Fingers that must touch an object for the hand to hold it: a majority of its fingers.
  int fingers_needed = 0;
};
HandGeometry measure_hand(core::Skillset& skills, const core::HandSpec& hand);

struct GraspCandidate {
  std::string id;      // family and index, e.g. "top.2"
  std::string family;  // "grip", "top", "side" or "part"
  // World: the centre of the grasped section (on the object's axis, the handle's axis), the
  // direction the hand moves in along its approach axis, and the direction its fingers close
  // along.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d approach = Eigen::Vector3d::UnitX();
  Eigen::Vector3d closing = Eigen::Vector3d::UnitY();
  double width_m = 0;       // the object's extent along `closing`
  double half_depth_m = 0;  // and against `approach`, from `centre` to its near side
  // The height of the object's bottom: the surface it stands on, which the fingers must not
  // reach (a finger stopped on it closes on nothing).
  double support_z = -INFINITY;
  // A world axis through `centre` about which the hand may turn and still hold the object
  // (the vertical for an upright object, a handle's axis), and how far; zero: none.
  Eigen::Vector3d free_axis = Eigen::Vector3d::Zero();
  double free_turn_rad = 0;
  double score = 0;  // lower is better
  // Tried only after every other candidate of the object found no way there (reach's second
  // round): the raised side grasps, the parts and the wrapped grasps. Reaching for the others
  // stays as it was.
  bool fallback = false;
  // A grasp wider than the hand's aperture, of a section this long across the hand (along
  // approach x closing): admitted where the fingers wrap it with the palm a centimetre off it
  // (wrapped_at; reach also tries it 2.5 cm off, where the estimate finds no wrap though
  // tallbot's hand holds a 104 mm jar so: the estimate leaves out the fingers' thickness, and
  // grasp counts the fingers that touch). Zero: the hand spans it. Such
  // grasps' ids have numbers of their own (`top.w0`), so the others' stay as they were.
  double wrap_length_m = 0;

  // Where the palm frame goes for the palm to stay `clearance` metres off the object's near
  // side (the palm is the hand's palm_depth_m behind its frame) with the grasped section no
  // nearer the palm than the closed fingers reach (closed_reach_m), and how far the hand may
  // turn about `free_axis` there: the turn is about the palm frame, so off the axis it is less.
  // A hand coming down is held back until its fingers stay over the support; `support_gap_m`:
  // how far the lowest finger point stays above the support there (negative: below it).
  struct Placement {
    core::Pose pose;
    double free_turn_rad = 0;
    double support_gap_m = INFINITY;
  };
  Placement place(const HandGeometry& hand, double clearance) const;
  // Whether the hand holds the object with the palm `clearance` off it: always, unless the
  // grasp needs the fingers to wrap it (wrap_length_m), and then where they wrap a round bar
  // of its width, its near side `clearance` off the palm (as a grasp pressed against the
  // palm).
  bool wrapped_at(const HandGeometry& hand, double clearance) const;
};

// A tool's handle: the shape nearest its grip frame, the grip point and the handle's axis
// (a capsule's or cylinder's own, else the grip frame's x axis). None without a grip frame.
struct Handle {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  core::Shape shape;
};
std::optional<Handle> tool_handle(const core::PerceivedObject& object);

// Whether points of a hand (world: the palm, its fingers' segments and tips) ring the handle:
// seen along its axis, the grip point lies inside their convex hull (with a margin), so the
// handle cannot leave the hand across its axis.
bool rings(const Handle& handle, const std::vector<Eigen::Vector3d>& points);

// The candidates for `object` with `hand`, best first. `from`: a point the hand comes from
// (its palm now).
std::vector<GraspCandidate> grasp_candidates(const core::PerceivedObject& object,
                                             const HandGeometry& hand, const Eigen::Vector3d& from);

// Notes (core::ProgramContext::notes) where reach records the candidate it moved to, and grasp
// the candidates that did not hold and what other than the object stopped a finger in them
// (reach then keeps the closing fingers off the surface under the object).
std::string reached_grasp_note(const std::string& object, const std::string& side);
std::string failed_grasps_note(const std::string& object, const std::string& side);
std::string blocked_fingers_note(const std::string& object, const std::string& side);

}  // namespace taskmatrix::programs
