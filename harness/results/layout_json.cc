#include "harness/results/layout_json.h"

namespace taskmatrix::harness {

nlohmann::json variation_json(const core::TaskVariation& v) {
  nlohmann::json j = nlohmann::json::object();
  if (!v.surfaces.empty()) {
    nlohmann::json s = nlohmann::json::object();
    for (const core::SurfaceDraw& d : v.surfaces)
      s[d.surface] = {{"height_m", d.height_m}, {"shift_m", d.shift_m}};
    j["surfaces"] = std::move(s);
  }
  if (!v.objects.empty()) {
    nlohmann::json o = nlohmann::json::object();
    for (const core::ObjectDraw& d : v.objects) {
      o[d.object] = {{"on", d.surface}, {"x", d.x}, {"y", d.y}, {"z", d.z}, {"yaw", d.yaw_rad}};
    }
    j["objects"] = std::move(o);
  }
  if (v.robot_start) {
    j["robot_start"] = {
        {"x", v.robot_start->x}, {"y", v.robot_start->y}, {"yaw", v.robot_start->yaw}};
    if (v.start_draw > 0) j["robot_start"]["draw"] = v.start_draw;
  }
  return j;
}

core::TaskVariation variation_from_json(const nlohmann::json& j) {
  core::TaskVariation v;
  if (const auto s = j.find("surfaces"); s != j.end()) {
    for (const auto& [name, d] : s->items()) {
      v.surfaces.push_back({name, d.at("height_m").get<double>(), d.at("shift_m").get<double>()});
    }
  }
  if (const auto o = j.find("objects"); o != j.end()) {
    for (const auto& [name, d] : o->items()) {
      v.objects.push_back({name, d.at("on").get<std::string>(), d.at("x").get<double>(),
                           d.at("y").get<double>(), d.at("z").get<double>(),
                           d.at("yaw").get<double>()});
    }
  }
  if (const auto r = j.find("robot_start"); r != j.end()) {
    v.robot_start = core::RobotStart{r->at("x").get<double>(), r->at("y").get<double>(),
                                     r->at("yaw").get<double>()};
    v.start_draw = r->value("draw", 0);
  }
  return v;
}

nlohmann::json layout_json(const core::TrialLayout& layout) {
  nlohmann::json j = variation_json(layout.variation);
  nlohmann::json obstacles = nlohmann::json::array();
  for (const core::PlacedObstacle& o : layout.obstacles.obstacles) {
    nlohmann::json item = {{"shape", core::to_string(o.shape)},
                           {"position", {o.position.x(), o.position.y(), o.position.z()}},
                           {"yaw", o.yaw},
                           {"size", {o.size.x(), o.size.y(), o.size.z()}}};
    if (o.group >= 0 && static_cast<size_t>(o.group) < layout.obstacles.groups.size()) {
      item["group"] = layout.obstacles.groups[static_cast<size_t>(o.group)];
    }
    if (o.hanging) item["hanging"] = true;
    obstacles.push_back(std::move(item));
  }
  j["obstacles"] = std::move(obstacles);
  if (layout.draw > 0) j["draw"] = layout.draw;
  return j;
}

}  // namespace taskmatrix::harness
