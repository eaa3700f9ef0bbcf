// Seeded random obstacle layouts. Pure geometry: the MuJoCo backend writes a layout into the
// reserved obstacle slots of a per-worker model copy (taskmatrix/mujoco/layout_apply.h).
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
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmatrix::core {

enum class ObstacleShape { kBox = 0, kCylinder = 1, kSphere = 2 };
const char* to_string(ObstacleShape shape);

struct Rect2 {
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
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
};

struct PlacedObstacle {
  ObstacleShape shape = ObstacleShape::kBox;
  int region = 0;            // index into LayoutRequest::regions
  Eigen::Vector3d position;  // centre, world frame
  double yaw = 0;            // about z
  Eigen::Vector3d size;      // MuJoCo geom size: box half extents; cylinder (r, half h); sphere (r)
  double footprint_radius = 0;  // radius of the circumscribing ground disk
};

struct ObstacleLayout {
  std::uint64_t seed = 0;
  std::vector<PlacedObstacle> obstacles;
};

class LayoutError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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
};

// Throws LayoutError when the request is inconsistent or `count` obstacles cannot be placed.
ObstacleLayout generate_layout(const LayoutRequest& request, std::uint64_t seed);

// Distance from a point to a rectangle in the plane (0 inside).
double distance_to_rect(double x, double y, const Rect2& rect);

}  // namespace taskmatrix::core
