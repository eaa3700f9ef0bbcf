// Seeded variations of a trial's world beyond its obstacles (scenario keys `objects:`,
// `surfaces:` and `robot_start:`, scenarios/README.md): where task objects stand on which
// surface and how they are turned, how high surfaces are, and where the robot starts. Pure
// geometry on a summary of the scene (WorldGeometry, made by the backend from the compiled
// model); the MuJoCo backend applies a TaskVariation to a worker's model copy and start state
// (WorkerScene::apply_variation) without recompiling anything.
//
// Rules.
//   - Surfaces: the height of each listed surface's top face is drawn uniformly from its range.
//     Whatever rests on a surface (objects, debris, the obstacles of its regions) moves with it.
//   - Robot start: offsets from the environment's start pose, each drawn uniformly.
//   - Objects: in the order listed, each object's centre is drawn uniformly within its
//     surface's placement area (the environment's obstacle region on that surface, or the top
//     face less 3 cm; for a top turned about the vertical without such a region, its own
//     rectangle less 3 cm, in its own axes: SurfaceGeometry::turned) or the sub-rectangle
//     `area` of it (fractions of the area along its x and y),
//     so that its footprint disk lies wholly inside that area and keeps `clearance_m` from
//     every object placed before it and from every task object (debris included) that is not
//     placed and still stands on that surface; its yaw (about the vertical, added to the
//     orientation it has in the model file) is drawn from its range, if it has one. It stands
//     kRestGapM above the surface at its drawn height and settles onto it under physics
//     (MuJoCo 2.2.2's box-box test reports faces that touch exactly, turned against each
//     other, as a contact tens of centimetres deep: a cup's base pad turned 0.4 rad on the
//     office's side table, 322 mm). Up to `max_attempts` draws per object, then
//     VariationError: never silently fewer.
//   - Each of the three kinds draws from its own stream of the layout seed, so adding one key
//     changes no other key's values, and a scenario without these keys draws nothing.
//   - A trial's world (draw_world) is the variation and then the obstacles placed in the world
//     it leaves. When this seed's draws do not fit (objects or obstacles crowded out), the
//     whole world is drawn again from the next derived seed, up to kWorldDraws times; the
//     record says which draw it is. A layout seed still names exactly one world.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/obstacle_layout.h"

namespace taskmatrix::core {

// How far above its surface a placed object starts, m (the rules above).
inline constexpr double kRestGapM = 1e-4;

// [min, max]; min == max: a fixed value.
struct ValueRange {
  double min = 0, max = 0;
};

// ---- What a scenario asks for.
struct ObjectPlacementOptions {
  std::string object;                 // a graspable or tool object
  std::string surface;                // a surface object
  Rect2 area{0.0, 1.0, 0.0, 1.0};     // fractions of the surface's placement area
  std::optional<ValueRange> yaw_rad;  // none: the orientation of the model file
};

struct SurfaceHeightOptions {
  std::string surface;
  ValueRange height_m;  // of the top face, above the floor
};

struct RobotStartOptions {
  ValueRange x_m, y_m, yaw_rad;  // offsets from the environment's robot_start
};

struct VariationOptions {
  std::vector<ObjectPlacementOptions> objects;
  std::vector<SurfaceHeightOptions> surfaces;
  std::optional<RobotStartOptions> robot_start;
  double clearance_m = 0.02;  // between placed objects and what they must keep clear of
  int max_attempts = 500;     // per object
  bool empty() const { return objects.empty() && surfaces.empty() && !robot_start; }
};

// ---- What the generator knows of a scene (from the compiled model).
// A top face turned about the vertical with its surface: the turn (cosine and sine) and the
// rectangle where objects are placed, in its own axes (the world's turned by it: a world point
// p lies at (cos p.x + sin p.y, -sin p.x + cos p.y) there).
struct TurnedArea {
  double cos = 1, sin = 0;
  Rect2 area;
};

struct SurfaceGeometry {
  std::string name;     // symbolic name ("work_surface")
  Rect2 top;            // the top face's extent (world-aligned)
  double height = 0;    // of the top face
  ObstacleRegion area;  // where things stand on it: its z is `height`
  // A top turned about the vertical, with no obstacle region of the environment's on it:
  // objects are placed within its own rectangle (less the margin `area` keeps), and `area`,
  // where obstacles go, is the largest world-aligned rectangle inside that.
  std::optional<TurnedArea> turned;
};

struct ObjectGeometry {
  std::string name;  // symbolic name; a debris flake by its body name
  ObjectKind kind = ObjectKind::kGraspable;
  double x = 0, y = 0, z = 0;  // body origin
  double radius = 0;           // footprint disk around the origin, any yaw
  double below = 0;            // origin above the object's lowest point
  double above = 0;            // object's highest point above the origin
  std::string rests_on;        // a surface's name, or "" (the floor, a hand, ...)
  Rect2 footprint;             // as compiled (the obstacle rule's protected rectangle)
};

struct WorldGeometry {
  std::vector<SurfaceGeometry> surfaces;
  std::vector<ObjectGeometry> objects;
  RobotStart start;
  const SurfaceGeometry* surface(const std::string& name) const;
  const ObjectGeometry* object(const std::string& name) const;
};

// ---- What was drawn (every value, for the trial's record).
struct SurfaceDraw {
  std::string surface;
  double height_m = 0;
  double shift_m = 0;  // from its height in the model file
};

struct ObjectDraw {
  std::string object, surface;
  double x = 0, y = 0, z = 0;  // body origin
  double yaw_rad = 0;          // added to the model file's orientation
};

struct TaskVariation {
  std::vector<SurfaceDraw> surfaces;
  std::vector<ObjectDraw> objects;
  std::optional<RobotStart> robot_start;  // the drawn pose (absolute)
  int start_draw = 0;  // which draw of the start it is (0: the first; draw_world redraws it)
  bool empty() const { return surfaces.empty() && objects.empty() && !robot_start; }
  const SurfaceDraw* surface(const std::string& name) const;
  const ObjectDraw* object(const std::string& name) const;
};

// A trial's whole drawn world: the variation and the obstacles placed after it.
struct TrialLayout {
  TaskVariation variation;
  ObstacleLayout obstacles;
  int draw = 0;  // which draw of the layout seed it is (draw_world)
};

// A draw that cannot be made, naming the scenario key at fault ("objects.cup").
class VariationError : public LayoutError {
 public:
  VariationError(std::string key, const std::string& message, bool crowded = false)
      : LayoutError(message, std::move(key), crowded) {}
};

inline constexpr int kWorldDraws = 20;
inline constexpr int kStartDraws = 50;

// What the robot, in its start posture at the variation's drawn start, touches in the world
// the variation leaves (its surfaces and objects; obstacles come after and keep clear of the
// start): a reason ("l_index touches table_top (depth 1.8 mm)"), or nullopt when it is clear.
using StartCheck = std::function<std::optional<std::string>(const TaskVariation&)>;

// The variation, then the obstacles of `request(variation)`; drawn again from derived seeds
// while they are crowded (LayoutError::crowded), at most kWorldDraws times. The first draw
// uses `seed` itself, so a scenario whose world fits at once draws what it drew before.
// With a varied `robot_start` and a `start_clear` check, a start at which the robot touches
// the varied world is drawn again (its own derived stream: surfaces and objects stay), at most
// kStartDraws times, before the obstacles are placed; the last start's reason is a
// VariationError of `robot_start`. A robot clear at its first draw draws what it drew before.
// Throws the last draw's LayoutError, or at once one that is not about crowding.
TrialLayout draw_world(const VariationOptions& options, const WorldGeometry& world,
                       const std::function<LayoutRequest(const TaskVariation&)>& request,
                       std::uint64_t seed, const StartCheck& start_clear = {});

// Checks the options against the geometry (names and kinds, ranges) and draws. Throws
// VariationError.
TaskVariation draw_variation(const VariationOptions& options, const WorldGeometry& world,
                             std::uint64_t seed);

// The geometry as the variation leaves it: surfaces at their drawn heights (their areas' z
// too), objects where they were placed or moved with their surface, the drawn start.
WorldGeometry varied(const WorldGeometry& world, const TaskVariation& variation);

// The obstacle groups of a scenario's targeted obstacles in the varied world: regions are the
// surfaces' placement areas (floor: the corridor from the robot's start to the surface, less
// `floor_keep_out`), zones around the objects' positions. Targeted obstacles are meant to be
// in the robot's way, so instead of the start clearance they keep clear of the robot's own
// footprint: `robot_radius` (every part of the robot), `robot_floor_radius` (its parts near
// the floor, for floor obstacles). Throws VariationError naming "obstacles.<kind>" for a name
// the world does not have.
std::vector<ObstacleGroup> targeted_groups(const std::vector<TargetedObstacles>& targeted,
                                           const WorldGeometry& world,
                                           const std::vector<Rect2>& floor_keep_out,
                                           double robot_radius, double robot_floor_radius);

}  // namespace taskmatrix::core
