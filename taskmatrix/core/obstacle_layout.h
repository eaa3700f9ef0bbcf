// Seeded random obstacle layouts. Pure geometry: the MuJoCo backend writes a layout into the
// reserved obstacle slots of a per-worker model copy (WorkerScene::apply_layout).
//
// Placement rule. Each obstacle's ground footprint is the disk circumscribing its projection
// (box: half-diagonal of its x/y half extents; cylinder and sphere: radius). An obstacle is
// accepted only if
//   - its whole footprint lies inside the region it was drawn in,
//   - its footprint keeps `clearance_m` from every protected disk (the robot's start
//     footprint), every protected rectangle (task objects, keep-out zones), the keep-out
//     rectangles of its own region (a table's footprint protects the floor, not the table
//     top) and every obstacle already placed, whatever region those are in.
// The region of each obstacle is drawn with probability proportional to region area, then
// shape, size, yaw and position are drawn; up to `max_attempts_per_obstacle` draws are tried
// before the generator gives up and throws LayoutError. It never silently places fewer.
// The same request and seed give the same layout on every platform (own uniform mapping on
// std::mt19937_64, no std distributions).
//
// Groups (obstacles placed where they interfere with a task). Before the random obstacles,
// each ObstacleGroup places its own count, drawn from its own stream of the seed: centres
// within a disk (around a task object) or a corridor (along a path), resting on or hanging
// over the group's regions. A hanging obstacle's bottom is drawn `lift` above its region;
// it may pass over what lies wholly below it (another obstacle, a protected rectangle whose
// `z_top` is lower), keeping `clearance_m` vertically. Every other rule above holds for group
// obstacles too, and the random obstacles then keep clear of them. A request without groups
// gives the same layout as before groups existed.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmatrix::core {

enum class ObstacleShape { kBox = 0, kCylinder = 1, kSphere = 2 };
const char* to_string(ObstacleShape shape);

struct Rect2 {
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  // As a protected area: what it protects lies below this height (a hanging obstacle may pass
  // over it); infinity: every height.
  double z_top = std::numeric_limits<double>::infinity();
};

struct ObstacleRegion {
  std::string name;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  double z = 0;                 // height of the surface obstacles rest on
  std::vector<Rect2> keep_out;  // protected in this region only (furniture on the floor)
};

struct Disk2 {
  double x = 0, y = 0, radius = 0;
};

// The points within `half_width` of the segment (x0, y0)-(x1, y1).
struct Corridor2 {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0, half_width = 0;
};

// Obstacles placed where they matter to a task (see the placement rule above).
struct ObstacleGroup {
  std::string name;  // what they are for ("near cup"): messages and the trial record
  std::string key;   // the scenario key it comes from, for errors ("obstacles.near")
  int count = 0;
  std::vector<ObstacleRegion> regions;  // surfaces they rest on (or hang over)
  std::vector<ObstacleShape> shapes{ObstacleShape::kBox, ObstacleShape::kCylinder,
                                    ObstacleShape::kSphere};
  double footprint_min_m = 0.02;
  double footprint_max_m = 0.05;
  double half_height_min_m = 0.03;
  double half_height_max_m = 0.12;
  std::optional<Disk2> within;     // centres within this disk
  std::optional<Corridor2> along;  // centres within this corridor
  bool hanging = false;            // hang over the regions, bottoms `lift` above their z
  double lift_min_m = 0, lift_max_m = 0;
  // Replace the request's protected disks for this group (e.g. the robot's own footprint
  // instead of its start clearance, for obstacles on the floor in front of it).
  std::optional<std::vector<Disk2>> protected_disks;
};

struct LayoutRequest {
  int count = 0;
  std::vector<ObstacleRegion> regions;
  std::vector<Disk2> protected_disks;
  std::vector<Rect2> protected_rects;
  std::vector<ObstacleShape> shapes{ObstacleShape::kBox, ObstacleShape::kCylinder,
                                    ObstacleShape::kSphere};
  double footprint_min_m = 0.04;  // half extent / radius range of the footprint
  double footprint_max_m = 0.12;
  double half_height_min_m = 0.05;  // half height range (boxes, cylinders)
  double half_height_max_m = 0.30;
  double clearance_m = 0.03;
  int max_attempts_per_obstacle = 500;
  std::vector<ObstacleGroup> groups;  // placed first, in order
};

struct PlacedObstacle {
  ObstacleShape shape = ObstacleShape::kBox;
  int region = 0;            // index into LayoutRequest::regions
  Eigen::Vector3d position;  // centre, world frame
  double yaw = 0;            // about z
  Eigen::Vector3d size;      // MuJoCo geom size: box half extents; cylinder (r, half h); sphere (r)
  double footprint_radius = 0;  // radius of the circumscribing ground disk
  int group = -1;               // index into LayoutRequest::groups; -1: a random obstacle
  bool hanging = false;
  double half_height() const;  // centre to top (and to bottom)
};

struct ObstacleLayout {
  std::uint64_t seed = 0;
  std::vector<PlacedObstacle> obstacles;
  std::vector<std::string> groups;  // names of the request's groups (PlacedObstacle::group)
};

// A layout that cannot be drawn. `key` names the scenario key at fault when one does (a
// group's "obstacles.near"); empty for the environment's own regions. `crowded`: the request
// is consistent but this seed's draws did not fit (another seed may).
class LayoutError : public std::runtime_error {
 public:
  explicit LayoutError(const std::string& message, std::string key = "", bool crowded = false)
      : std::runtime_error(message), key_(std::move(key)), crowded_(crowded) {}
  const std::string& key() const { return key_; }
  bool crowded() const { return crowded_; }

 private:
  std::string key_;
  bool crowded_;
};

// Obstacles a scenario places where they interfere with the task (obstacles.near, .path,
// .overhead, .floor in scenarios/README.md); the backend resolves the names into an
// ObstacleGroup with the trial's drawn positions.
struct TargetedObstacles {
  enum class Kind { kNear, kPath, kOverhead, kFloor };
  Kind kind = Kind::kNear;
  int count = 0;
  std::string object;   // near, overhead: around this object; path: from it
  std::string surface;  // near, overhead: on/over this surface (without object); path, floor: to it
  double radius_m = 0.25;                       // near, overhead: centres within this of the object
  double width_m = 0.3;                         // path, floor: corridor width
  double lift_min_m = 0.25, lift_max_m = 0.45;  // overhead: bottom above the surface
  std::vector<ObstacleShape> shapes{ObstacleShape::kBox, ObstacleShape::kCylinder,
                                    ObstacleShape::kSphere};
  double footprint_min_m = 0.02, footprint_max_m = 0.05;
  double half_height_min_m = 0.03, half_height_max_m = 0.12;
};
const char* to_string(TargetedObstacles::Kind kind);
// The defaults of a kind (sizes, shapes, radius, width), before the scenario's keys.
TargetedObstacles targeted_defaults(TargetedObstacles::Kind kind);

// What a scenario asks of a layout; the backend turns it into a LayoutRequest with the
// environment's regions and protected areas.
struct ObstacleOptions {
  int count = 0;
  std::vector<std::string> regions;  // names of the environment's regions; empty: all
  std::vector<ObstacleShape> shapes{ObstacleShape::kBox, ObstacleShape::kCylinder,
                                    ObstacleShape::kSphere};
  double footprint_min_m = 0.04;  // as LayoutRequest
  double footprint_max_m = 0.12;
  double half_height_min_m = 0.05;
  double half_height_max_m = 0.30;
  std::vector<TargetedObstacles> targeted;  // placed before the random ones
  int total() const;                        // count plus every targeted count
};

// Throws LayoutError when the request is inconsistent or `count` obstacles cannot be placed.
ObstacleLayout generate_layout(const LayoutRequest& request, std::uint64_t seed);

// Distance from a point to a rectangle in the plane (0 inside).
double distance_to_rect(double x, double y, const Rect2& rect);
// Distance from a point to a corridor's centre segment.
double distance_to_segment(double x, double y, const Corridor2& corridor);

}  // namespace taskmatrix::core
