#include "harness/scenario/scenario_variation.h"

#include <cmath>
#include <tuple>

namespace taskmatrix::harness {

namespace {

core::ValueRange read_range(const io::YamlNode& node, const char* unit, bool positive) {
  if (node.is_scalar()) {
    const double v = node.as_double();
    if (positive && !(v > 0)) node.fail(std::string("must be above 0 ") + unit);
    return {v, v};
  }
  const std::vector<double> v = node.as_doubles();
  if (v.size() != 2 || !(v[0] <= v[1])) {
    node.fail(std::string("must be a number or [min, max] with min <= max (") + unit + ")");
  }
  if (positive && !(v[0] > 0)) node.fail(std::string("must be above 0 ") + unit);
  return {v[0], v[1]};
}

void note(KeyLines& lines, const io::YamlNode& node, const std::string& key) {
  lines[key] = node.line();
}

std::vector<core::ObstacleShape> read_shapes(const io::YamlNode& node) {
  std::vector<core::ObstacleShape> out;
  for (const std::string& name : node.as_strings()) {
    if (name == "box") {
      out.push_back(core::ObstacleShape::kBox);
    } else if (name == "cylinder") {
      out.push_back(core::ObstacleShape::kCylinder);
    } else if (name == "sphere") {
      out.push_back(core::ObstacleShape::kSphere);
    } else {
      node.fail("unknown shape '" + name + "' (known: box, cylinder, sphere)");
    }
  }
  if (out.empty()) node.fail("needs at least one shape");
  return out;
}

std::pair<double, double> read_size(const io::YamlNode& node) {
  const core::ValueRange r = read_range(node, "m", true);
  return {r.min, r.max};
}

core::TargetedObstacles read_targeted(const io::YamlNode& node, core::TargetedObstacles::Kind kind,
                                      KeyLines& lines) {
  using Kind = core::TargetedObstacles::Kind;
  core::TargetedObstacles t = core::targeted_defaults(kind);
  const std::string key = std::string("obstacles.") + core::to_string(kind);
  note(lines, node, key);
  switch (kind) {
    case Kind::kNear:
      node.expect_keys(
          {"object", "surface", "radius_m", "count", "shapes", "footprint_m", "half_height_m"});
      break;
    case Kind::kOverhead:
      node.expect_keys(
          {"object", "surface", "radius_m", "count", "height_m", "footprint_m", "half_height_m"});
      break;
    case Kind::kPath:
      node.expect_keys(
          {"from", "to", "width_m", "count", "shapes", "footprint_m", "half_height_m"});
      break;
    case Kind::kFloor:
      node.expect_keys({"to", "width_m", "count", "shapes", "footprint_m", "half_height_m"});
      break;
  }
  const io::YamlNode count = node.required("count");
  t.count = count.as_int();
  if (t.count < 0 || t.count > 200) count.fail("must be in 0..200");
  auto name = [&](const char* k, std::string& out) {
    if (auto n = node.optional(k)) {
      out = n->as_string();
      note(lines, *n, key + "." + k);
    }
  };
  if (kind == Kind::kNear || kind == Kind::kOverhead) {
    name("object", t.object);
    name("surface", t.surface);
    if (t.object.empty() == t.surface.empty()) node.fail("needs exactly one of object and surface");
    if (auto r = node.optional("radius_m")) {
      if (t.object.empty()) r->fail("applies only around an object");
      t.radius_m = r->as_positive_double();
    }
  } else {
    if (kind == Kind::kPath) {
      name("from", t.object);
      if (t.object.empty()) node.required("from");
    }
    name("to", t.surface);
    if (t.surface.empty()) node.required("to");
    if (auto w = node.optional("width_m")) t.width_m = w->as_positive_double();
  }
  if (auto h = node.optional("height_m")) {
    const core::ValueRange r = read_range(*h, "m above the surface", false);
    if (!(r.min >= 0)) h->fail("must not be below 0 m");
    t.lift_min_m = r.min;
    t.lift_max_m = r.max;
  }
  if (auto s = node.optional("shapes")) t.shapes = read_shapes(*s);
  if (auto f = node.optional("footprint_m"))
    std::tie(t.footprint_min_m, t.footprint_max_m) = read_size(*f);
  if (auto h = node.optional("half_height_m")) {
    std::tie(t.half_height_min_m, t.half_height_max_m) = read_size(*h);
  }
  return t;
}

}  // namespace

int line_of(const KeyLines& lines, const std::string& key) {
  for (std::string k = key; !k.empty();) {
    const auto it = lines.find(k);
    if (it != lines.end()) return it->second;
    const size_t dot = k.rfind('.');
    if (dot == std::string::npos) break;
    k = k.substr(0, dot);
  }
  return 0;
}

core::VariationOptions read_variation(const io::YamlNode& root, KeyLines& lines) {
  core::VariationOptions out;
  if (auto objects = root.optional("objects")) {
    note(lines, *objects, "objects");
    for (const auto& [name, node] : objects->entries()) {
      const std::string key = "objects." + name;
      note(lines, node, key);
      node.expect_keys({"on", "area", "yaw"});
      core::ObjectPlacementOptions p;
      p.object = name;
      const io::YamlNode on = node.required("on");
      p.surface = on.as_string();
      note(lines, on, key + ".on");
      if (auto area = node.optional("area")) {
        note(lines, *area, key + ".area");
        area->expect_keys({"x", "y"});
        for (const char* axis : {"x", "y"}) {
          const auto v = area->optional(axis);
          if (!v) continue;
          const std::vector<double> f = v->as_doubles();
          if (f.size() != 2 || !(f[0] >= 0 && f[0] < f[1] && f[1] <= 1)) {
            v->fail("must be [min, max] fractions of the surface with 0 <= min < max <= 1");
          }
          (axis[0] == 'x' ? p.area.x_min : p.area.y_min) = f[0];
          (axis[0] == 'x' ? p.area.x_max : p.area.y_max) = f[1];
        }
      }
      if (auto yaw = node.optional("yaw")) {
        note(lines, *yaw, key + ".yaw");
        p.yaw_rad = read_range(*yaw, "rad", false);
        if (p.yaw_rad->max - p.yaw_rad->min > 2 * M_PI + 1e-6) {
          yaw->fail("must span at most one turn (2 pi rad)");
        }
      }
      out.objects.push_back(p);
    }
    if (out.objects.empty()) objects->fail("needs at least one object");
  }
  if (auto surfaces = root.optional("surfaces")) {
    note(lines, *surfaces, "surfaces");
    for (const auto& [name, node] : surfaces->entries()) {
      const std::string key = "surfaces." + name;
      note(lines, node, key);
      node.expect_keys({"height_m"});
      const io::YamlNode h = node.required("height_m");
      note(lines, h, key + ".height_m");
      core::SurfaceHeightOptions s{name, read_range(h, "m", true)};
      if (s.height_m.max > 3) h.fail("must be at most 3 m");
      out.surfaces.push_back(s);
    }
    if (out.surfaces.empty()) surfaces->fail("needs at least one surface");
  }
  if (auto start = root.optional("robot_start")) {
    note(lines, *start, "robot_start");
    start->expect_keys({"x", "y", "yaw"});
    core::RobotStartOptions r;
    auto offset = [&](const char* k, core::ValueRange& v, const char* unit, double limit) {
      if (auto n = start->optional(k)) {
        note(lines, *n, std::string("robot_start.") + k);
        v = read_range(*n, unit, false);
        if (std::abs(v.min) > limit || std::abs(v.max) > limit) {
          n->fail("must stay within +-" + std::to_string(limit).substr(0, 4) + " " + unit +
                  " of the environment's start");
        }
      }
    };
    offset("x", r.x_m, "m", 2.0);
    offset("y", r.y_m, "m", 2.0);
    offset("yaw", r.yaw_rad, "rad", M_PI);
    out.robot_start = r;
  }
  return out;
}

void read_targeted_obstacles(const io::YamlNode& obstacles, core::ObstacleOptions& options,
                             KeyLines& lines) {
  using Kind = core::TargetedObstacles::Kind;
  for (const Kind kind : {Kind::kNear, Kind::kPath, Kind::kOverhead, Kind::kFloor}) {
    const auto node = obstacles.optional(core::to_string(kind));
    if (!node) continue;
    if (node->is_map()) {
      options.targeted.push_back(read_targeted(*node, kind, lines));
    } else {
      for (const io::YamlNode& item : node->items())
        options.targeted.push_back(read_targeted(item, kind, lines));
    }
  }
}

}  // namespace taskmatrix::harness
