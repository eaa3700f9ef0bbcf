#include "taskmatrix/core/task_variation.h"

#include <algorithm>
#include <cmath>

#include "taskmatrix/core/uniform_draws.h"

namespace taskmatrix::core {

namespace {

// Streams of the layout seed (obstacle groups use 0x100 and up).
constexpr std::uint64_t kStartStream = 1, kSurfaceStream = 2, kObjectStream = 3;

void check_range(const ValueRange& r, const std::string& key, const char* unit) {
  if (!std::isfinite(r.min) || !std::isfinite(r.max) || r.min > r.max) {
    throw VariationError(key, std::string("must be [min, max] with min <= max (") + unit + ")");
  }
}

double draw(UniformDraws& rng, const ValueRange& r) {
  return r.min == r.max ? r.min : rng.in(r.min, r.max);
}

// The k-th draw of the start: the first from the layout seed's start stream, later ones from
// streams derived from it.
RobotStart draw_start(const RobotStartOptions& r, const RobotStart& start, std::uint64_t seed,
                      int k) {
  const std::uint64_t stream = stream_seed(seed, kStartStream);
  UniformDraws rng(k == 0 ? stream : stream_seed(stream, static_cast<std::uint64_t>(k)));
  const double dx = draw(rng, r.x_m), dy = draw(rng, r.y_m), dyaw = draw(rng, r.yaw_rad);
  return RobotStart{start.x + dx, start.y + dy, start.yaw + dyaw};
}

std::string known_names(const WorldGeometry& world, bool surfaces) {
  std::string out;
  if (surfaces) {
    for (const SurfaceGeometry& s : world.surfaces) out += (out.empty() ? "" : ", ") + s.name;
  } else {
    for (const ObjectGeometry& o : world.objects) {
      if (o.kind == ObjectKind::kGraspable || o.kind == ObjectKind::kTool)
        out += (out.empty() ? "" : ", ") + o.name;
    }
  }
  return out.empty() ? "none" : out;
}

const SurfaceGeometry& require_surface(const WorldGeometry& world, const std::string& name,
                                       const std::string& key) {
  const SurfaceGeometry* s = world.surface(name);
  if (!s) {
    throw VariationError(key, "no surface '" + name + "' in this environment (surfaces: " +
                                  known_names(world, true) + ")");
  }
  return *s;
}

const ObjectGeometry& require_object(const WorldGeometry& world, const std::string& name,
                                     const std::string& key) {
  const ObjectGeometry* o = world.object(name);
  if (!o || !(o->kind == ObjectKind::kGraspable || o->kind == ObjectKind::kTool)) {
    throw VariationError(key, "no graspable object or tool '" + name +
                                  "' in this environment (known: " + known_names(world, false) +
                                  ")");
  }
  return *o;
}

Rect2 bounds_of(const ObstacleRegion& r) { return {r.x_min, r.x_max, r.y_min, r.y_max}; }

}  // namespace

const SurfaceGeometry* WorldGeometry::surface(const std::string& name) const {
  for (const SurfaceGeometry& s : surfaces) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const ObjectGeometry* WorldGeometry::object(const std::string& name) const {
  for (const ObjectGeometry& o : objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

const SurfaceDraw* TaskVariation::surface(const std::string& name) const {
  for (const SurfaceDraw& s : surfaces) {
    if (s.surface == name) return &s;
  }
  return nullptr;
}

const ObjectDraw* TaskVariation::object(const std::string& name) const {
  for (const ObjectDraw& o : objects) {
    if (o.object == name) return &o;
  }
  return nullptr;
}

TaskVariation draw_variation(const VariationOptions& options, const WorldGeometry& world,
                             std::uint64_t seed) {
  TaskVariation out;
  if (options.robot_start) {
    const RobotStartOptions& r = *options.robot_start;
    check_range(r.x_m, "robot_start.x", "m");
    check_range(r.y_m, "robot_start.y", "m");
    check_range(r.yaw_rad, "robot_start.yaw", "rad");
    out.robot_start = draw_start(r, world.start, seed, 0);
  }
  if (!options.surfaces.empty()) {
    UniformDraws rng(stream_seed(seed, kSurfaceStream));
    for (const SurfaceHeightOptions& s : options.surfaces) {
      const std::string key = "surfaces." + s.surface;
      const SurfaceGeometry& g = require_surface(world, s.surface, key);
      check_range(s.height_m, key + ".height_m", "m");
      if (!(s.height_m.min > 0)) throw VariationError(key + ".height_m", "must be above 0 m");
      if (out.surface(s.surface)) throw VariationError(key, "is listed twice");
      const double h = draw(rng, s.height_m);
      out.surfaces.push_back({s.surface, h, h - g.height});
    }
  }
  if (options.objects.empty()) return out;

  const WorldGeometry lifted = varied(world, out);
  UniformDraws rng(stream_seed(seed, kObjectStream));
  struct Disk {
    double x, y, r;
  };
  std::vector<Disk> placed;
  for (const ObjectPlacementOptions& p : options.objects) {
    const std::string key = "objects." + p.object;
    const ObjectGeometry& obj = require_object(lifted, p.object, key);
    const SurfaceGeometry& surface = require_surface(lifted, p.surface, key + ".on");
    if (out.object(p.object)) throw VariationError(key, "is listed twice");
    const Rect2& f = p.area;
    if (!(f.x_min >= 0 && f.x_min < f.x_max && f.x_max <= 1 && f.y_min >= 0 && f.y_min < f.y_max &&
          f.y_max <= 1)) {
      throw VariationError(key + ".area",
                           "x and y must be [min, max] fractions with 0 <= min < max <= 1");
    }
    if (p.yaw_rad) check_range(*p.yaw_rad, key + ".yaw", "rad");
    // In the top's own axes where it is turned (the fractions along its own sides).
    const Rect2 a = surface.turned ? surface.turned->area
                                   : Rect2{surface.area.x_min, surface.area.x_max,
                                           surface.area.y_min, surface.area.y_max};
    const double c = surface.turned ? surface.turned->cos : 1;
    const double s = surface.turned ? surface.turned->sin : 0;
    const double w = a.x_max - a.x_min, d = a.y_max - a.y_min;
    const Rect2 area{a.x_min + f.x_min * w, a.x_min + f.x_max * w, a.y_min + f.y_min * d,
                     a.y_min + f.y_max * d};
    const double r = obj.radius;
    if (area.x_max - area.x_min < 2 * r || area.y_max - area.y_min < 2 * r) {
      throw VariationError(key, "'" + p.object + "' (footprint radius " + std::to_string(r) +
                                    " m) does not fit in its area of " + p.surface);
    }
    // What it must keep clear of: objects placed before it, and objects that stay on this
    // surface (not placed by this variation).
    std::vector<Disk> keep = placed;
    for (const ObjectGeometry& other : lifted.objects) {
      if (other.name == p.object || other.rests_on != p.surface) continue;
      const bool to_be_placed =
          std::any_of(options.objects.begin(), options.objects.end(),
                      [&](const ObjectPlacementOptions& q) { return q.object == other.name; });
      if (!to_be_placed) keep.push_back({other.x, other.y, other.radius});
    }
    bool ok = false;
    ObjectDraw drawn;
    for (int attempt = 0; attempt < options.max_attempts && !ok; ++attempt) {
      double x = rng.in(area.x_min + r, area.x_max - r);
      double y = rng.in(area.y_min + r, area.y_max - r);
      if (surface.turned) {
        const double u = x, v = y;
        x = c * u - s * v;
        y = s * u + c * v;
      }
      const double yaw = p.yaw_rad ? draw(rng, *p.yaw_rad) : 0.0;
      ok = std::all_of(keep.begin(), keep.end(),
                       [&](const Disk& k) {
                         return std::hypot(x - k.x, y - k.y) >= k.r + r + options.clearance_m;
                       }) &&
           std::all_of(surface.area.keep_out.begin(), surface.area.keep_out.end(),
                       [&](const Rect2& k) {
                         return distance_to_rect(x, y, k) >= r + options.clearance_m;
                       });
      drawn = {p.object, p.surface, x, y, surface.height + obj.below + kRestGapM, yaw};
    }
    if (!ok) {
      throw VariationError(key,
                           "cannot place '" + p.object + "' on " + p.surface + " (seed " +
                               std::to_string(seed) + ", " + std::to_string(options.max_attempts) +
                               " draws): its area is too crowded",
                           true);
    }
    placed.push_back({drawn.x, drawn.y, r});
    out.objects.push_back(drawn);
  }
  return out;
}

TrialLayout draw_world(const VariationOptions& options, const WorldGeometry& world,
                       const std::function<LayoutRequest(const TaskVariation&)>& request,
                       std::uint64_t seed, const StartCheck& start_clear) {
  for (int draw = 0;; ++draw) {
    const std::uint64_t s = draw == 0 ? seed : stream_seed(seed, 0x1000 + draw);
    try {
      TrialLayout out;
      out.draw = draw;
      out.variation = draw_variation(options, world, s);
      if (options.robot_start && start_clear) {
        TaskVariation& v = out.variation;
        while (const std::optional<std::string> why = start_clear(v)) {
          if (v.start_draw + 1 >= kStartDraws) {
            throw VariationError(
                "robot_start", "no start drawn in its ranges leaves the robot clear (" +
                                   std::to_string(kStartDraws) + " draws; the last: " + *why + ")");
          }
          v.robot_start = draw_start(*options.robot_start, world.start, s, ++v.start_draw);
        }
      }
      out.obstacles = generate_layout(request(out.variation), s);
      out.obstacles.seed = seed;
      return out;
    } catch (const LayoutError& e) {
      if (!e.crowded() || draw + 1 >= kWorldDraws) {
        if (!e.crowded()) throw;
        throw LayoutError(std::string(e.what()) + "; " + std::to_string(kWorldDraws) +
                              " draws of the layout seed were all too crowded",
                          e.key(), true);
      }
    }
  }
}

WorldGeometry varied(const WorldGeometry& world, const TaskVariation& variation) {
  WorldGeometry out = world;
  for (SurfaceGeometry& s : out.surfaces) {
    const SurfaceDraw* d = variation.surface(s.name);
    if (!d) continue;
    s.height = d->height_m;
    s.area.z = d->height_m;
  }
  for (ObjectGeometry& o : out.objects) {
    if (const ObjectDraw* d = variation.object(o.name)) {
      o.x = d->x;
      o.y = d->y;
      o.z = d->z;
      o.rests_on = d->surface;
      o.footprint = {o.x - o.radius, o.x + o.radius, o.y - o.radius, o.y + o.radius};
    } else if (const SurfaceDraw* s = variation.surface(o.rests_on)) {
      o.z += s->shift_m;
    } else {
      continue;
    }
    o.footprint.z_top = o.z + o.above;
  }
  if (variation.robot_start) out.start = *variation.robot_start;
  return out;
}

std::vector<ObstacleGroup> targeted_groups(const std::vector<TargetedObstacles>& targeted,
                                           const WorldGeometry& world,
                                           const std::vector<Rect2>& floor_keep_out,
                                           double robot_radius, double robot_floor_radius) {
  std::vector<ObstacleGroup> out;
  for (const TargetedObstacles& t : targeted) {
    const std::string key = std::string("obstacles.") + to_string(t.kind);
    ObstacleGroup g;
    g.key = key;
    g.count = t.count;
    g.protected_disks = std::vector<Disk2>{{world.start.x, world.start.y, robot_radius}};
    g.shapes = t.shapes;
    g.footprint_min_m = t.footprint_min_m;
    g.footprint_max_m = t.footprint_max_m;
    g.half_height_min_m = t.half_height_min_m;
    g.half_height_max_m = t.half_height_max_m;
    // The object's surface, or the named one.
    auto object_or_surface = [&]() -> const SurfaceGeometry& {
      if (t.object.empty()) return require_surface(world, t.surface, key + ".surface");
      const ObjectGeometry& o = require_object(world, t.object, key + ".object");
      if (o.rests_on.empty()) {
        throw VariationError(key + ".object", "'" + t.object + "' rests on no surface");
      }
      g.within = Disk2{o.x, o.y, t.radius_m};
      return require_surface(world, o.rests_on, key + ".object");
    };
    switch (t.kind) {
      case TargetedObstacles::Kind::kNear:
      case TargetedObstacles::Kind::kOverhead: {
        const SurfaceGeometry& s = object_or_surface();
        g.regions = {s.area};
        const std::string what = t.object.empty() ? s.name : t.object;
        if (t.kind == TargetedObstacles::Kind::kNear) {
          g.name = "obstacles near " + what;
        } else {
          g.name = "obstacles over " + what;
          g.hanging = true;
          g.lift_min_m = t.lift_min_m;
          g.lift_max_m = t.lift_max_m;
        }
        break;
      }
      case TargetedObstacles::Kind::kPath: {
        const ObjectGeometry& o = require_object(world, t.object, key + ".from");
        const SurfaceGeometry& to = require_surface(world, t.surface, key + ".to");
        const double cx = (to.area.x_min + to.area.x_max) / 2;
        const double cy = (to.area.y_min + to.area.y_max) / 2;
        g.name = "obstacles on the path from " + t.object + " to " + t.surface;
        g.along = Corridor2{o.x, o.y, cx, cy, t.width_m / 2};
        for (const SurfaceGeometry& s : world.surfaces) {
          const Rect2 b = bounds_of(s.area);
          const double gap = std::max({0.0, std::min(o.x, cx) - t.width_m / 2 - b.x_max,
                                       b.x_min - std::max(o.x, cx) - t.width_m / 2,
                                       std::min(o.y, cy) - t.width_m / 2 - b.y_max,
                                       b.y_min - std::max(o.y, cy) - t.width_m / 2});
          if (gap <= 0) g.regions.push_back(s.area);
        }
        break;
      }
      case TargetedObstacles::Kind::kFloor: {
        const SurfaceGeometry& to = require_surface(world, t.surface, key + ".to");
        const double sx = world.start.x, sy = world.start.y;
        const double px = std::clamp(sx, to.top.x_min, to.top.x_max);
        const double py = std::clamp(sy, to.top.y_min, to.top.y_max);
        const double hw = t.width_m / 2;
        g.name = "obstacles on the floor before " + t.surface;
        g.along = Corridor2{sx, sy, px, py, hw};
        ObstacleRegion floor;
        floor.name = "floor before " + t.surface;
        floor.x_min = std::min(sx, px) - hw;
        floor.x_max = std::max(sx, px) + hw;
        floor.y_min = std::min(sy, py) - hw;
        floor.y_max = std::max(sy, py) + hw;
        floor.z = 0;
        floor.keep_out = floor_keep_out;
        for (const SurfaceGeometry& s : world.surfaces) floor.keep_out.push_back(s.top);
        g.regions = {floor};
        g.protected_disks = std::vector<Disk2>{{sx, sy, robot_floor_radius}};
        break;
      }
    }
    out.push_back(std::move(g));
  }
  return out;
}

}  // namespace taskmatrix::core
