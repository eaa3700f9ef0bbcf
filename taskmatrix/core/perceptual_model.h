// The perceptual model (paper section III-B): what the robot believes about the objects
// around it. A perception process outside the programs (ground truth, or the simulated head
// sensor) writes it at its own rate; programs and conditions only read it.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/planning_types.h"

namespace taskmatrix::core {

// The ids things are perceived by (docs/perception.md): an environment's object by its name
// when it is one body, else each of its bodies by the body's name (the debris flakes); the
// visitor as "visitor"; the obstacle of slot `slot` as "obstacle_<slot>".
inline const std::string& perceived_id(const std::string& name, const ObjectSpec& spec,
                                       const std::string& body) {
  return spec.bodies.size() == 1 ? name : body;
}
inline constexpr const char* kVisitorId = "visitor";
inline constexpr std::string_view kObstacleIdPrefix = "obstacle_";
inline std::string obstacle_id(int slot) {
  return std::string(kObstacleIdPrefix) + std::to_string(slot);
}

// One primitive of an object's collision geometry, as perception reports it (recognition
// knows the model of what it recognises): programs derive grasps from these.
struct Shape {
  enum class Type { kBox, kSphere, kCapsule, kCylinder, kEllipsoid };
  Type type = Type::kBox;
  Pose pose;  // world; capsules and cylinders lie along the pose's z axis
  // Half extents (box, ellipsoid); radius and half-length (capsule: of its segment, cylinder);
  // radius (sphere, in x).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  // Half extent of the shape along the world unit direction `u` (its support width).
  double half_width(const Eigen::Vector3d& u) const;
  // The world-aligned box round it.
  Eigen::AlignedBox3d bounds() const;
};

struct PerceivedObject {
  std::string id;    // symbolic name: "cup", "debris_2", "work_surface", "obstacle_4", "visitor"
  std::string type;  // "graspable", "tool", "surface", "debris", "obstacle", "humanoid"
  Pose pose;         // of the object's frame
  Eigen::AlignedBox3d box;                                      // world-aligned bounding box
  double last_seen = -std::numeric_limits<double>::infinity();  // simulated seconds
  double confidence = 0;  // in [0, 1]: 1 for ground truth; for the sensor, its visible share
  // Named frames the object's model declares: a tool's "grip" (where a hand holds it) and
  // "tip" (its working end).
  std::map<std::string, Pose, std::less<>> frames;
  // The collision geometry (empty when perception knows only the box).
  std::vector<Shape> shapes;
  // A surface's top face seen from above, in the surface's own upright frame (`pose`): the
  // extent of its top slab along that frame's x and y axes, from its origin. Empty for other
  // objects, and where perception knows only the box; surface_top() reads it.
  Eigen::AlignedBox2d top;

  // Where a hand grasps it: the "grip" frame's position if it has one, else the box centre.
  Eigen::Vector3d grasp_point() const {
    const auto grip = frames.find("grip");
    return grip != frames.end() ? grip->second.position : box.center();
  }
};

// A surface's top face seen from above: a rectangle turned about the vertical with the
// surface's frame (a surface's frame is upright, models/README.md), so that a table standing at
// an angle in a room is not taken for its world-aligned bounding box, whose corners lie beside
// it. `lo` and `hi` bound it along its own axes, measured from the world's origin: a point's
// coordinates there are local(). A surface whose frame is not turned (or known only by its box)
// is its box's footprint, exactly: local() is then the identity.
struct SurfaceTop {
  double cos = 1, sin = 0;  // of the turn of its axes from the world's x and y
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
  double height = 0;  // of the top face

  bool turned() const { return sin != 0 || cos != 1; }
  // A world point (seen from above) in the top's axes, and back.
  Eigen::Vector2d local(const Eigen::Vector2d& world) const;
  Eigen::Vector2d world(const Eigen::Vector2d& local) const;
  // Half extents along the top's axes of a world-aligned footprint with half extents `half`.
  Eigen::Vector2d extent(const Eigen::Vector2d& half) const;
  // The distance from the world point `p` to the rectangle; negative inside it (how far in from
  // its nearest edge).
  double signed_distance(const Eigen::Vector2d& p) const;
  // The point of the rectangle nearest the world point `p` (`p` itself inside it).
  Eigen::Vector2d nearest(const Eigen::Vector2d& p) const;
  // Whether the world-aligned footprint [lo, hi] overlaps the rectangle (touching counts).
  bool overlaps(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const;
  // The largest world-aligned rectangle centred in it (its footprint where not turned): where
  // things are set down when only world-aligned rectangles can be given.
  Eigen::AlignedBox2d inscribed() const;
};

// The top of a surface whose world-aligned box is `box`, frame `pose` and top extent in that
// frame `top` (PerceivedObject::top; empty: the box's footprint).
SurfaceTop surface_top(const Eigen::AlignedBox3d& box, const Pose& pose,
                       const Eigen::AlignedBox2d& top);
inline SurfaceTop surface_top(const PerceivedObject& surface) {
  return surface_top(surface.box, surface.pose, surface.top);
}

// How far a shape must stick out beyond the rest of its object to count as a part of its own.
constexpr double kProtrudingPartM = 0.01;

// The shapes of an object of several that stick out sideways beyond the rest by at least
// kProtrudingPartM (a mug's handle): seen from the middle of the object's extent, horizontally
// towards the shape, its far side lies that much farther out than every other shape's. Their
// indices in `object.shapes`; none for an object of fewer than two shapes.
std::vector<size_t> protruding_shapes(const PerceivedObject& object);

class PerceptualModel {
 public:
  // Inserts or replaces the object with the same id.
  void observe(PerceivedObject object);
  void forget(std::string_view id);
  void clear() { objects_.clear(); }

  const PerceivedObject* find(std::string_view id) const;
  std::vector<const PerceivedObject*> of_type(std::string_view type) const;
  const std::map<std::string, PerceivedObject, std::less<>>& objects() const { return objects_; }
  bool knows(std::string_view id) const { return find(id) != nullptr; }

 private:
  std::map<std::string, PerceivedObject, std::less<>> objects_;
};

// A perception process: called by the executive at its own rate, it updates the model.
class Perception {
 public:
  virtual ~Perception() = default;
  virtual const char* mode() const = 0;  // "ground_truth" or "sensor"
  virtual void update(double time, PerceptualModel& model) = 0;
};

}  // namespace taskmatrix::core
