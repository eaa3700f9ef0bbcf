#include "taskmatrix/core/obstacle_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "taskmatrix/core/uniform_draws.h"

namespace taskmatrix::core {

const char* to_string(ObstacleShape shape) {
  switch (shape) {
    case ObstacleShape::kBox:
      return "box";
    case ObstacleShape::kCylinder:
      return "cylinder";
    case ObstacleShape::kSphere:
      return "sphere";
  }
  return "?";
}

double distance_to_rect(double x, double y, const Rect2& rect) {
  const double dx = std::max({rect.x_min - x, 0.0, x - rect.x_max});
  const double dy = std::max({rect.y_min - y, 0.0, y - rect.y_max});
  return std::hypot(dx, dy);
}

double PlacedObstacle::half_height() const {
  return shape == ObstacleShape::kSphere ? size.x()
         : shape == ObstacleShape::kBox  ? size.z()
                                         : size.y();
}

double distance_to_segment(double x, double y, const Corridor2& c) {
  const double dx = c.x1 - c.x0, dy = c.y1 - c.y0;
  const double length2 = dx * dx + dy * dy;
  const double t =
      length2 > 0 ? std::clamp(((x - c.x0) * dx + (y - c.y0) * dy) / length2, 0.0, 1.0) : 0.0;
  return std::hypot(x - (c.x0 + t * dx), y - (c.y0 + t * dy));
}

const char* to_string(TargetedObstacles::Kind kind) {
  switch (kind) {
    case TargetedObstacles::Kind::kNear:
      return "near";
    case TargetedObstacles::Kind::kPath:
      return "path";
    case TargetedObstacles::Kind::kOverhead:
      return "overhead";
    case TargetedObstacles::Kind::kFloor:
      return "floor";
  }
  return "?";
}

TargetedObstacles targeted_defaults(TargetedObstacles::Kind kind) {
  TargetedObstacles t;
  t.kind = kind;
  switch (kind) {
    case TargetedObstacles::Kind::kNear:
    case TargetedObstacles::Kind::kPath:
      break;  // small things on a table: the struct's defaults
    case TargetedObstacles::Kind::kOverhead:
      t.radius_m = 0.3;
      t.shapes = {ObstacleShape::kBox};
      t.footprint_min_m = 0.05;
      t.footprint_max_m = 0.15;
      t.half_height_min_m = 0.01;
      t.half_height_max_m = 0.05;
      break;
    case TargetedObstacles::Kind::kFloor:
      t.width_m = 1.0;
      t.footprint_min_m = 0.04;
      t.footprint_max_m = 0.10;
      t.half_height_min_m = 0.03;
      t.half_height_max_m = 0.15;
      break;
  }
  return t;
}

int ObstacleOptions::total() const {
  int n = count;
  for (const TargetedObstacles& t : targeted) n += t.count;
  return n;
}

namespace {

// What a group's draws need; the random obstacles are a group too (without zone).
struct Draws {
  std::string name;
  std::string key;
  int count = 0;
  const std::vector<ObstacleRegion>* regions = nullptr;
  const std::vector<ObstacleShape>* shapes = nullptr;
  double footprint_min = 0, footprint_max = 0, half_min = 0, half_max = 0;
  const Disk2* within = nullptr;
  const Corridor2* along = nullptr;
  bool hanging = false;
  double lift_min = 0, lift_max = 0;
  const std::vector<Disk2>* disks = nullptr;
  int group = -1;
};

void check_sizes(double f_min, double f_max, double h_min, double h_max, const std::string& what) {
  if (!(f_min > 0 && f_min <= f_max) || !(h_min > 0 && h_min <= h_max)) {
    throw LayoutError(what + ": obstacle size ranges must be positive with min <= max");
  }
}

Rect2 zone_bounds(const Draws& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Rect2 b{-inf, inf, -inf, inf};
  if (d.within) {
    b = {d.within->x - d.within->radius, d.within->x + d.within->radius,
         d.within->y - d.within->radius, d.within->y + d.within->radius};
  }
  if (d.along) {
    const Corridor2& c = *d.along;
    b = {std::max(b.x_min, std::min(c.x0, c.x1) - c.half_width),
         std::min(b.x_max, std::max(c.x0, c.x1) + c.half_width),
         std::max(b.y_min, std::min(c.y0, c.y1) - c.half_width),
         std::min(b.y_max, std::max(c.y0, c.y1) + c.half_width)};
  }
  return b;
}

// The part of `r` inside `b` (may be empty: max < min).
Rect2 clip(const ObstacleRegion& r, const Rect2& b) {
  return {std::max(r.x_min, b.x_min), std::min(r.x_max, b.x_max), std::max(r.y_min, b.y_min),
          std::min(r.y_max, b.y_max)};
}

double area(const Rect2& r) {
  return std::max(0.0, r.x_max - r.x_min) * std::max(0.0, r.y_max - r.y_min);
}

// Places d.count obstacles into `layout`; throws LayoutError naming the group when it cannot.
void place(const Draws& d, const LayoutRequest& req, UniformDraws& rng, ObstacleLayout& layout) {
  const Rect2 bounds = zone_bounds(d);
  std::vector<double> areas;
  double total_area = 0;
  for (const ObstacleRegion& r : *d.regions) {
    // The random obstacles keep the original weighting (whole regions, no zone).
    areas.push_back(d.group < 0 ? area(Rect2{r.x_min, r.x_max, r.y_min, r.y_max})
                                : area(clip(r, bounds)));
    total_area += areas.back();
  }
  if (d.count > 0 && !(total_area > 0)) {
    throw LayoutError(d.name + ": no region overlaps where its obstacles must go", d.key);
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < d.count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < req.max_attempts_per_obstacle && !placed; ++attempt) {
      // Region by area.
      double pick = rng.next() * total_area;
      int region = 0;
      while (region + 1 < static_cast<int>(d.regions->size()) && pick >= areas[region]) {
        pick -= areas[region];
        ++region;
      }
      const ObstacleRegion& r = (*d.regions)[region];

      PlacedObstacle o;
      o.region = region;
      o.group = d.group;
      o.hanging = d.hanging;
      o.shape = (*d.shapes)[rng.index(d.shapes->size())];
      const double a = rng.in(d.footprint_min, d.footprint_max);
      const double b = rng.in(d.footprint_min, d.footprint_max);
      const double h = rng.in(d.half_min, d.half_max);
      o.yaw = rng.in(-std::numbers::pi, std::numbers::pi);
      double half_height = h;
      switch (o.shape) {
        case ObstacleShape::kBox:
          o.size = {a, b, h};
          o.footprint_radius = std::hypot(a, b);
          break;
        case ObstacleShape::kCylinder:
          o.size = {a, h, 0};
          o.footprint_radius = a;
          break;
        case ObstacleShape::kSphere:
          o.size = {a, 0, 0};
          o.footprint_radius = a;
          half_height = a;
          o.yaw = 0;
          break;
      }
      const double fr = o.footprint_radius;
      if (r.x_max - r.x_min < 2 * fr || r.y_max - r.y_min < 2 * fr) continue;
      double x_lo = r.x_min + fr, x_hi = r.x_max - fr, y_lo = r.y_min + fr, y_hi = r.y_max - fr;
      if (d.group >= 0) {
        x_lo = std::max(x_lo, bounds.x_min);
        x_hi = std::min(x_hi, bounds.x_max);
        y_lo = std::max(y_lo, bounds.y_min);
        y_hi = std::min(y_hi, bounds.y_max);
        if (x_lo > x_hi || y_lo > y_hi) continue;
      }
      const double x = rng.in(x_lo, x_hi);
      const double y = rng.in(y_lo, y_hi);
      const double lift = d.hanging ? rng.in(d.lift_min, d.lift_max) : 0.0;
      o.position = {x, y, r.z + lift + half_height};
      if (d.within && std::hypot(x - d.within->x, y - d.within->y) > d.within->radius) continue;
      if (d.along && distance_to_segment(x, y, *d.along) > d.along->half_width) continue;

      const double bottom = o.position.z() - half_height;
      const double c = req.clearance_m;
      bool clear = true;
      for (const Disk2& disk : *d.disks) {
        clear = clear && std::hypot(x - disk.x, y - disk.y) >= disk.radius + fr + c;
      }
      for (const std::vector<Rect2>* rects : {&req.protected_rects, &r.keep_out}) {
        for (const Rect2& rect : *rects) {
          const bool passes_over = d.hanging && rect.z_top < inf && bottom >= rect.z_top + c;
          clear = clear && (passes_over || distance_to_rect(x, y, rect) >= fr + c);
        }
      }
      for (const PlacedObstacle& other : layout.obstacles) {
        const bool apart = std::hypot(x - other.position.x(), y - other.position.y()) >=
                           fr + other.footprint_radius + c;
        bool stacked = false;  // one wholly above the other, only when either hangs
        if (o.hanging || other.hanging) {
          const double hb = other.half_height();
          stacked = bottom >= other.position.z() + hb + c ||
                    other.position.z() - hb >= o.position.z() + half_height + c;
        }
        clear = clear && (apart || stacked);
      }
      if (clear) {
        layout.obstacles.push_back(o);
        placed = true;
      }
    }
    if (!placed) {
      throw LayoutError("could place only " + std::to_string(i) + " of " + std::to_string(d.count) +
                            " " + d.name + " (seed " + std::to_string(layout.seed) + ", " +
                            std::to_string(req.max_attempts_per_obstacle) +
                            " attempts for the next one): the regions are too crowded",
                        d.key, true);
    }
  }
}

}  // namespace

ObstacleLayout generate_layout(const LayoutRequest& req, std::uint64_t seed) {
  if (req.count < 0) throw LayoutError("obstacle count must not be negative");
  if (req.count > 0 && req.regions.empty()) throw LayoutError("no obstacle region to place in");
  if (req.shapes.empty()) throw LayoutError("no obstacle shape allowed");
  check_sizes(req.footprint_min_m, req.footprint_max_m, req.half_height_min_m,
              req.half_height_max_m, "random obstacles");
  if (!(req.clearance_m >= 0)) throw LayoutError("obstacle clearance must not be negative");
  auto check_regions = [](const std::vector<ObstacleRegion>& regions) {
    for (const ObstacleRegion& r : regions) {
      if (!(r.x_max > r.x_min && r.y_max > r.y_min) || !std::isfinite(r.z)) {
        throw LayoutError("obstacle region '" + r.name + "' is empty or not finite");
      }
    }
  };
  check_regions(req.regions);

  ObstacleLayout layout;
  layout.seed = seed;
  for (const ObstacleGroup& group : req.groups) layout.groups.push_back(group.name);
  for (size_t g = 0; g < req.groups.size(); ++g) {
    const ObstacleGroup& group = req.groups[g];
    if (group.count < 0) throw LayoutError(group.name + ": count must not be negative");
    if (group.count == 0) continue;
    if (group.regions.empty()) throw LayoutError(group.name + ": no region to place in");
    if (group.shapes.empty()) throw LayoutError(group.name + ": no obstacle shape allowed");
    check_sizes(group.footprint_min_m, group.footprint_max_m, group.half_height_min_m,
                group.half_height_max_m, group.name);
    if (group.hanging && !(group.lift_min_m >= 0 && group.lift_min_m <= group.lift_max_m)) {
      throw LayoutError(group.name + ": the lift range must be 0 <= min <= max");
    }
    check_regions(group.regions);
    Draws d{group.name,
            group.key,
            group.count,
            &group.regions,
            &group.shapes,
            group.footprint_min_m,
            group.footprint_max_m,
            group.half_height_min_m,
            group.half_height_max_m,
            group.within ? &*group.within : nullptr,
            group.along ? &*group.along : nullptr,
            group.hanging,
            group.lift_min_m,
            group.lift_max_m,
            group.protected_disks ? &*group.protected_disks : &req.protected_disks,
            static_cast<int>(g)};
    // A stream of its own: adding a group changes no other group's draws.
    UniformDraws rng(stream_seed(seed, 0x100 + g));
    place(d, req, rng, layout);
  }
  UniformDraws rng(seed);
  Draws random{"obstacles",
               "",
               req.count,
               &req.regions,
               &req.shapes,
               req.footprint_min_m,
               req.footprint_max_m,
               req.half_height_min_m,
               req.half_height_max_m,
               nullptr,
               nullptr,
               false,
               0,
               0,
               &req.protected_disks,
               -1};
  place(random, req, rng, layout);
  return layout;
}

}  // namespace taskmatrix::core
