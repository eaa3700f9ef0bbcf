#include "taskmatrix/core/obstacle_layout.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace taskmatrix::core {
namespace {

// Uniform in [0, 1) from the top 53 bits: identical on every standard library.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  double next() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double in(double lo, double hi) { return lo + (hi - lo) * next(); }
  size_t index(size_t n) { return std::min(n - 1, static_cast<size_t>(next() * n)); }

 private:
  std::mt19937_64 engine_;
};

double area(const ObstacleRegion& r) { return (r.x_max - r.x_min) * (r.y_max - r.y_min); }

}  // namespace

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

ObstacleLayout generate_layout(const LayoutRequest& req, std::uint64_t seed) {
  if (req.count < 0) throw LayoutError("obstacle count must not be negative");
  if (req.count > 0 && req.regions.empty()) throw LayoutError("no obstacle region to place in");
  if (req.shapes.empty()) throw LayoutError("no obstacle shape allowed");
  if (!(req.footprint_min_m > 0 && req.footprint_min_m <= req.footprint_max_m) ||
      !(req.half_height_min_m > 0 && req.half_height_min_m <= req.half_height_max_m) ||
      !(req.clearance_m >= 0)) {
    throw LayoutError("obstacle size ranges must be positive with min <= max");
  }
  double total_area = 0;
  for (const ObstacleRegion& r : req.regions) {
    if (!(r.x_max > r.x_min && r.y_max > r.y_min) || !std::isfinite(r.z)) {
      throw LayoutError("obstacle region '" + r.name + "' is empty or not finite");
    }
    total_area += area(r);
  }

  Uniform rng(seed);
  ObstacleLayout layout;
  layout.seed = seed;
  for (int i = 0; i < req.count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < req.max_attempts_per_obstacle && !placed; ++attempt) {
      // Region by area.
      double pick = rng.next() * total_area;
      int region = 0;
      while (region + 1 < static_cast<int>(req.regions.size()) &&
             pick >= area(req.regions[region])) {
        pick -= area(req.regions[region]);
        ++region;
      }
      const ObstacleRegion& r = req.regions[region];

      PlacedObstacle o;
      o.region = region;
      o.shape = req.shapes[rng.index(req.shapes.size())];
      const double a = rng.in(req.footprint_min_m, req.footprint_max_m);
      const double b = rng.in(req.footprint_min_m, req.footprint_max_m);
      const double h = rng.in(req.half_height_min_m, req.half_height_max_m);
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
      const double x = rng.in(r.x_min + fr, r.x_max - fr);
      const double y = rng.in(r.y_min + fr, r.y_max - fr);
      o.position = {x, y, r.z + half_height};

      bool clear = true;
      for (const Disk2& d : req.protected_disks) {
        clear = clear && std::hypot(x - d.x, y - d.y) >= d.radius + fr + req.clearance_m;
      }
      for (const std::vector<Rect2>* rects : {&req.protected_rects, &r.keep_out}) {
        for (const Rect2& rect : *rects) {
          clear = clear && distance_to_rect(x, y, rect) >= fr + req.clearance_m;
        }
      }
      for (const PlacedObstacle& other : layout.obstacles) {
        clear = clear && std::hypot(x - other.position.x(), y - other.position.y()) >=
                             fr + other.footprint_radius + req.clearance_m;
      }
      if (clear) {
        layout.obstacles.push_back(o);
        placed = true;
      }
    }
    if (!placed) {
      throw LayoutError("could place only " + std::to_string(i) + " of " +
                        std::to_string(req.count) + " obstacles (seed " + std::to_string(seed) +
                        ", " + std::to_string(req.max_attempts_per_obstacle) +
                        " attempts for the next one): the regions are too crowded");
    }
  }
  return layout;
}

}  // namespace taskmatrix::core
