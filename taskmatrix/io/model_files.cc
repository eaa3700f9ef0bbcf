#include "taskmatrix/io/model_files.h"

#include <algorithm>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::io {

using core::InputError;

namespace {

std::filesystem::path existing_file(const YamlNode& node, const std::filesystem::path& dir) {
  const std::filesystem::path p = (dir / node.as_string()).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec))
    node.fail("file '" + p.string() + "' does not exist");
  return p;
}

void expect_name_matches_folder(const YamlNode& name, const std::filesystem::path& file) {
  const std::string folder = file.parent_path().filename().string();
  if (name.as_string() != folder) {
    name.fail("is '" + name.as_string() + "' but the folder is '" + folder + "'");
  }
}

core::CameraSpec read_camera(const YamlNode& node) {
  core::CameraSpec cam;
  if (node.is_scalar()) {
    cam.name = node.as_string();
    return cam;
  }
  node.expect_keys({"name", "body", "pos", "xyaxes", "fovy"});
  cam.declared_in_profile = true;
  cam.name = node.required("name").as_string();
  cam.body = node.required("body").as_string();
  const YamlNode pos = node.required("pos");
  const std::vector<double> p = pos.as_doubles();
  if (p.size() != 3) pos.fail("must hold 3 numbers");
  std::copy(p.begin(), p.end(), cam.pos.begin());
  if (auto xy = node.optional("xyaxes")) {
    const std::vector<double> v = xy->as_doubles();
    if (v.size() != 6) xy->fail("must hold 6 numbers");
    std::copy(v.begin(), v.end(), cam.xyaxes.begin());
  }
  cam.fovy_deg = node.get_double("fovy", 60.0);
  if (cam.fovy_deg <= 1 || cam.fovy_deg >= 179)
    node.required("fovy").fail("must be in (1, 179) degrees");
  return cam;
}

core::Rect2 read_rect(const YamlNode& node) {
  const YamlNode x = node.required("x");
  const YamlNode y = node.required("y");
  const std::vector<double> xs = x.as_doubles(), ys = y.as_doubles();
  if (xs.size() != 2 || xs[0] >= xs[1]) x.fail("must be [min, max] with min < max");
  if (ys.size() != 2 || ys[0] >= ys[1]) y.fail("must be [min, max] with min < max");
  return {xs[0], xs[1], ys[0], ys[1]};
}

}  // namespace

core::RobotProfile load_robot_profile(const std::filesystem::path& profile_file) {
  const YamlNode root = YamlNode::load_file(profile_file);
  root.expect_keys({"name", "model", "urdf", "height_m", "chains", "head_camera", "hands",
                    "postures", "speed_limits", "mirror_signs", "canned", "actuator_kp",
                    "description"});
  const std::filesystem::path dir = profile_file.parent_path();
  core::RobotProfile p;
  p.profile_file = profile_file;
  const YamlNode name = root.required("name");
  expect_name_matches_folder(name, profile_file);
  p.name = name.as_string();
  if (root.has("model") == root.has("urdf")) {
    root.fail("exactly one of 'model' (MJCF) and 'urdf' must be given");
  }
  if (auto model = root.optional("model")) {
    p.model_file = existing_file(*model, dir);
    p.format = core::ModelFormat::kMjcf;
  } else {
    p.model_file = existing_file(root.required("urdf"), dir);
    p.format = core::ModelFormat::kUrdf;
  }
  p.height_m = root.required("height_m").as_positive_double();

  for (const auto& [chain_name, node] : root.required("chains").entries()) {
    node.expect_keys({"joints", "end_effector"});
    core::ChainSpec chain;
    chain.name = chain_name;
    chain.joints = node.required("joints").as_strings();
    chain.end_effector = node.get_string("end_effector", "");
    p.chains.push_back(chain);
  }
  p.head_camera = read_camera(root.required("head_camera"));
  if (p.format == core::ModelFormat::kUrdf && !p.head_camera.declared_in_profile) {
    root.required("head_camera")
        .fail("a URDF robot must declare its camera as {name, body, pos, xyaxes, fovy}");
  }

  for (const auto& [side, node] : root.required("hands").entries()) {
    node.expect_keys({"palm", "approach", "closing", "fingers"});
    core::HandSpec hand;
    hand.side = side;
    hand.palm = node.required("palm").as_string();
    const YamlNode approach = node.required("approach");
    const std::vector<double> axis = approach.as_doubles();
    if (axis.size() != 3) approach.fail("must be a unit vector [x, y, z] in the palm frame");
    hand.approach = {axis[0], axis[1], axis[2]};
    const YamlNode closing = node.required("closing");
    const std::vector<double> closing_axis = closing.as_doubles();
    if (closing_axis.size() != 3) closing.fail("must be a unit vector [x, y, z] in the palm frame");
    hand.closing = {closing_axis[0], closing_axis[1], closing_axis[2]};
    for (const YamlNode& f : node.required("fingers").items()) {
      f.expect_keys({"joints", "bodies"});
      hand.fingers.push_back(
          {f.required("joints").as_strings(), f.required("bodies").as_strings()});
    }
    p.hands.push_back(hand);
  }

  for (const auto& [posture_name, node] : root.required("postures").entries()) {
    core::Posture posture;
    for (const auto& [chain_name, values] : node.entries()) {
      posture[chain_name] = values.as_doubles();
    }
    p.postures[posture_name] = posture;
  }
  for (const auto& [chain_name, node] : root.required("speed_limits").entries()) {
    node.expect_keys({"velocity", "acceleration"});
    p.speed_limits[chain_name] = {node.required("velocity").as_positive_double(),
                                  node.required("acceleration").as_positive_double()};
  }
  for (const auto& [kind, node] : root.required("mirror_signs").entries()) {
    p.mirror_signs[kind] = node.as_doubles();
  }
  if (auto canned = root.optional("canned")) {
    for (const auto& [motion_name, node] : canned->entries()) {
      node.expect_keys({"chains", "keyframes"});
      core::CannedMotion motion;
      motion.chains = node.required("chains").as_strings();
      for (const YamlNode& k : node.required("keyframes").items()) {
        std::vector<double> row = k.as_doubles();
        if (row.size() < 2) k.fail("must be [time_s, joint values...]");
        motion.keyframes.push_back({row[0], std::vector<double>(row.begin() + 1, row.end())});
      }
      p.canned[motion_name] = std::move(motion);
    }
  }
  if (auto kp = root.optional("actuator_kp")) {
    for (const auto& [chain_name, value] : kp->entries()) {
      p.actuator_kp[chain_name] = value.as_positive_double();
    }
  }
  core::validate_profile_structure(p);
  return p;
}

core::EnvironmentSpec load_environment_spec(const std::filesystem::path& spec_file) {
  const YamlNode root = YamlNode::load_file(spec_file);
  root.expect_keys({"name", "model", "robot_start", "start_clearance_m", "objects", "visitor",
                    "keep_out", "obstacle_regions", "obstacle_slots", "cameras", "description"});
  const std::filesystem::path dir = spec_file.parent_path();
  core::EnvironmentSpec env;
  env.spec_file = spec_file;
  const YamlNode name = root.required("name");
  expect_name_matches_folder(name, spec_file);
  env.name = name.as_string();
  env.model_file = existing_file(root.required("model"), dir);

  const YamlNode start = root.required("robot_start");
  start.expect_keys({"x", "y", "yaw"});
  env.robot_start = {start.get_double("x", 0), start.get_double("y", 0),
                     start.get_double("yaw", 0)};
  env.start_clearance_m = root.get_double("start_clearance_m", 0.6);
  if (env.start_clearance_m < 0) root.required("start_clearance_m").fail("must not be negative");

  for (const auto& [obj_name, node] : root.required("objects").entries()) {
    node.expect_keys({"body", "bodies", "kind", "tip_site", "grip_site"});
    core::ObjectSpec obj;
    obj.name = obj_name;
    const YamlNode kind = node.required("kind");
    const std::string k = kind.as_string();
    if (k == "graspable")
      obj.kind = core::ObjectKind::kGraspable;
    else if (k == "tool")
      obj.kind = core::ObjectKind::kTool;
    else if (k == "surface")
      obj.kind = core::ObjectKind::kSurface;
    else if (k == "debris")
      obj.kind = core::ObjectKind::kDebris;
    else
      kind.fail("must be one of graspable, tool, surface, debris; got '" + k + "'");
    if (node.has("body") == node.has("bodies"))
      node.fail("needs exactly one of 'body' and 'bodies'");
    if (auto b = node.optional("body"))
      obj.bodies = {b->as_string()};
    else
      obj.bodies = node.required("bodies").as_strings();
    obj.tip_site = node.get_string("tip_site", "");
    obj.grip_site = node.get_string("grip_site", "");
    if (obj.kind == core::ObjectKind::kTool && obj.tip_site.empty()) {
      node.fail("a tool needs a 'tip_site'");
    }
    env.objects[obj_name] = obj;
  }

  if (auto visitor = root.optional("visitor")) {
    visitor->expect_keys({"body", "path"});
    env.visitor.body = visitor->required("body").as_string();
    if (auto path = visitor->optional("path")) {
      for (const YamlNode& wp : path->items()) {
        const std::vector<double> v = wp.as_doubles();
        if (v.size() != 2) wp.fail("a waypoint is [x, y]");
        env.visitor.path.push_back({v[0], v[1]});
      }
    }
  }
  if (auto regions = root.optional("obstacle_regions")) {
    for (const YamlNode& r : regions->items()) {
      r.expect_keys({"name", "x", "y", "z"});
      const core::Rect2 rect = read_rect(r);
      env.obstacle_regions.push_back({r.required("name").as_string(),
                                      rect.x_min,
                                      rect.x_max,
                                      rect.y_min,
                                      rect.y_max,
                                      r.get_double("z", 0.0),
                                      {}});
    }
  }
  // A keep-out rectangle protects every region, or only the regions it names.
  if (auto keep_out = root.optional("keep_out")) {
    for (const YamlNode& item : keep_out->items()) {
      item.expect_keys({"x", "y", "name", "regions"});
      const core::Rect2 rect = read_rect(item);
      auto only = item.optional("regions");
      if (!only) {
        env.keep_out.push_back(rect);
        continue;
      }
      for (const YamlNode& region_name : only->items()) {
        const std::string n = region_name.as_string();
        auto it = std::find_if(env.obstacle_regions.begin(), env.obstacle_regions.end(),
                               [&](const core::ObstacleRegion& r) { return r.name == n; });
        if (it == env.obstacle_regions.end()) region_name.fail("names no obstacle region");
        it->keep_out.push_back(rect);
      }
    }
  }
  env.obstacle_slots = root.get_int("obstacle_slots", 0);
  if (env.obstacle_slots < 0 || env.obstacle_slots > 200) {
    root.required("obstacle_slots").fail("must be between 0 and 200");
  }
  if (auto cameras = root.optional("cameras")) env.cameras = cameras->as_strings();
  return env;
}

}  // namespace taskmatrix::io
