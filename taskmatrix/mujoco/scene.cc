#include "taskmatrix/mujoco/scene.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/joint_limits.h"
#include "taskmatrix/io/model_files.h"
#include "taskmatrix/io/text_file.h"
#include "taskmatrix/mujoco/mjcf_compose.h"
#include "taskmatrix/mujoco/urdf_import.h"

namespace taskmatrix::mujoco {

using core::InputError;

namespace {

std::filesystem::path required_file(const std::filesystem::path& dir, const char* name) {
  const std::filesystem::path p = dir / name;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(dir.string(), "", "no such folder");
  if (!std::filesystem::is_regular_file(p, ec)) throw InputError(p.string(), "", "missing");
  return p;
}

bool near_axis(const mjtNum* axis, double x, double y, double z) {
  return std::abs(axis[0] - x) < 1e-6 && std::abs(axis[1] - y) < 1e-6 &&
         std::abs(axis[2] - z) < 1e-6;
}

// MuJoCo's body-pair filter (engine_collision_driver): same weld body, or weld parent/child.
bool body_pair_filtered(const mjModel* m, int b1, int b2) {
  const int w1 = m->body_weldid[b1], w2 = m->body_weldid[b2];
  if (w1 == w2) return true;
  const int p1 = m->body_weldid[m->body_parentid[w1]], p2 = m->body_weldid[m->body_parentid[w2]];
  const bool filter_parent = !(m->opt.disableflags & mjDSBL_FILTERPARENT);
  return filter_parent && w1 != 0 && w2 != 0 && (w1 == p2 || w2 == p1);
}

bool excluded(const mjModel* m, int b1, int b2) {
  const int lo = std::min(b1, b2), hi = std::max(b1, b2);
  const int signature = ((lo + 1) << 16) + hi + 1;
  for (int i = 0; i < m->nexclude; ++i) {
    if (m->exclude_signature[i] == signature) return true;
  }
  return false;
}

// The head camera convention the programs rely on (models/README.md, "The head camera"):
// MuJoCo cameras look along their -z with the image's x to the right and y up. With the
// robot at its rest posture and its base at the origin (facing +x), the optical axis must
// point forward (within 80 degrees of +x), the image must be upright (x horizontal within 5
// degrees, pointing to the robot's right; y upwards): fixate turns the base by the image's
// horizontal angle. The head chain must move the camera: fixate and explore aim it with it;
// a robot without a head chain (a camera fixed to the trunk) must have it on a body the base
// moves, and they aim it with the base's yaw.
void check_head_camera(const Scene& scene, const std::string& pfile) {
  const mjModel* m = scene.model();
  DataPtr d = make_data(m);
  std::copy(scene.start_qpos().begin(), scene.start_qpos().end(), d->qpos);
  for (int adr : scene.chain("base").qpos_adr) d->qpos[adr] = 0;
  mj_kinematics(m, d.get());
  mj_camlight(m, d.get());
  const int cam = scene.head_camera();
  const mjtNum* r = d->cam_xmat + 9 * cam;  // columns: the camera's x, y, z axes
  const double image_x[3] = {r[0], r[3], r[6]}, image_y[3] = {r[1], r[4], r[7]};
  const double ahead[3] = {-r[2], -r[5], -r[8]};
  const std::string name = "camera '" + scene.robot().head_camera.name + "'";
  auto degrees = [](double cosine) {
    return std::to_string(
        static_cast<int>(std::lround(std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI)));
  };
  if (ahead[0] < std::cos(80.0 * M_PI / 180.0)) {
    throw InputError(pfile, "head_camera",
                     name + " looks " + degrees(ahead[0]) +
                         " degrees away from the robot's forward +x at rest (at most 80; a "
                         "MuJoCo camera looks along its -z)");
  }
  if (std::abs(image_x[2]) > std::sin(5.0 * M_PI / 180.0) || image_x[1] >= 0 || image_y[2] <= 0) {
    throw InputError(pfile, "head_camera",
                     name +
                         " is not upright at rest: its image x axis must be horizontal and "
                         "point to the robot's right (-y), its y axis up (e.g. xyaxes=\"0 -1 "
                         "0 0 0 1\" in a head frame facing +x)");
  }
  const int cam_body = m->cam_bodyid[cam];
  const bool head = scene.robot().find_chain("head") != nullptr;
  for (int j : scene.chain(head ? "head" : "base").joints) {
    for (int b = cam_body; b > 0; b = m->body_parentid[b]) {
      if (b == m->jnt_bodyid[j]) return;
    }
  }
  throw InputError(pfile, "head_camera",
                   head ? name +
                              " is not on a body the head chain moves (fixate and explore "
                              "aim the camera with the head joints)"
                        : name +
                              " is not on a body the base moves (the robot has no head "
                              "chain: fixate and explore aim the camera with the base)");
}

}  // namespace

Eigen::Vector2d horizontal_half_extent(const mjModel* m, const mjData* d, int g) {
  const double* size = m->geom_size + 3 * g;
  Eigen::Vector3d local;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE:
      local = Eigen::Vector3d::Constant(size[0]);
      break;
    case mjGEOM_CAPSULE:
      local = Eigen::Vector3d(size[0], size[0], size[1] + size[0]);
      break;
    case mjGEOM_CYLINDER:
      local = Eigen::Vector3d(size[0], size[0], size[1]);
      break;
    case mjGEOM_BOX:
    case mjGEOM_ELLIPSOID:
      local = Eigen::Vector3d(size[0], size[1], size[2]);
      break;
    default:
      return Eigen::Vector2d::Constant(m->geom_rbound[g]);
  }
  const double* r = d->geom_xmat + 9 * g;  // row-major: world = R * local
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) {
    out[i] = std::abs(r[3 * i]) * local.x() + std::abs(r[3 * i + 1]) * local.y() +
             std::abs(r[3 * i + 2]) * local.z();
  }
  return out;
}

std::shared_ptr<const Scene> Scene::load(const std::filesystem::path& robot_dir,
                                         const std::filesystem::path& environment_dir) {
  std::shared_ptr<Scene> scene(new Scene());
  scene->robot_ = io::load_robot_profile(required_file(robot_dir, "profile.yaml"));
  scene->environment_ =
      io::load_environment_spec(required_file(environment_dir, "environment.yaml"));
  const core::RobotProfile& robot = scene->robot_;
  const core::EnvironmentSpec& env = scene->environment_;

  // Each file compiles on its own first, so MuJoCo's errors name the right file and line.
  MjcfSource robot_src{"", robot.model_file.string()};
  if (robot.format == core::ModelFormat::kUrdf) {
    robot_src.text = import_urdf_as_mjcf(robot);
  } else {
    compile_file(robot.model_file.string());
    robot_src.text = io::read_text_file(robot.model_file);
  }
  compile_file(env.model_file.string());
  const MjcfSource env_src{io::read_text_file(env.model_file), env.model_file.string()};

  CompositionOptions options;
  options.model_name = robot.name + "@" + env.name;
  options.obstacle_slots = env.obstacle_slots;
  scene->composed_mjcf_ = compose_scene_mjcf(robot_src, env_src, options);
  scene->model_ = compile_mjcf_text(scene->composed_mjcf_,
                                    robot.model_file.string() + " in " + env.model_file.string());
  scene->index_and_validate();
  return scene;
}

void Scene::index_and_validate() {
  const mjModel* m = model_.get();
  const std::string pfile = robot_.profile_file.string();
  const std::string efile = environment_.spec_file.string();
  const std::string mfile = robot_.model_file.string();

  // The robot's tree: the top-level body above the first base joint.
  const core::ChainSpec* base_spec = robot_.find_chain("base");
  const int base_joint = mj_name2id(m, mjOBJ_JOINT, base_spec->joints[0].c_str());
  if (base_joint < 0) {
    throw InputError(pfile, "chains.base.joints",
                     "joint '" + base_spec->joints[0] + "' is not in " + mfile);
  }
  robot_root_ = m->body_rootid[m->jnt_bodyid[base_joint]];

  // Chains: hinge or slide joints of the robot, limited with finite ranges.
  for (const core::ChainSpec& spec : robot_.chains) {
    ChainIndex chain;
    chain.name = spec.name;
    const std::string key = "chains." + spec.name + ".joints";
    for (const std::string& name : spec.joints) {
      const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
      if (j < 0) throw InputError(pfile, key, "joint '" + name + "' is not in " + mfile);
      if (m->jnt_type[j] == mjJNT_FREE) {
        throw InputError(pfile, key,
                         "joint '" + name +
                             "' is a free joint (a floating base): the harness moves a robot on "
                             "a planar base; replace it in " +
                             mfile +
                             " with a slide joint along x, a slide joint along y and a hinge "
                             "about z (models/README.md, 'A robot')");
      }
      if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) {
        throw InputError(pfile, key, "joint '" + name + "' must be a hinge or slide joint");
      }
      if (!is_robot_body(m->jnt_bodyid[j])) {
        throw InputError(pfile, key, "joint '" + name + "' is not on the robot's body tree");
      }
      const double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
      if (!m->jnt_limited[j] || !std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) {
        throw InputError(pfile, key, "joint '" + name + "' needs finite limits with lower < upper");
      }
      chain.joints.push_back(j);
      chain.qpos_adr.push_back(m->jnt_qposadr[j]);
      chain.lower.push_back(lo);
      chain.upper.push_back(hi);
    }
    chains_.push_back(chain);
  }

  // The base: slide x, slide y, hinge z on the robot's root tree.
  const ChainIndex& base = chain("base");
  const int bx = base.joints[0], by = base.joints[1], byaw = base.joints[2];
  if (m->jnt_type[bx] != mjJNT_SLIDE || !near_axis(m->jnt_axis + 3 * bx, 1, 0, 0) ||
      m->jnt_type[by] != mjJNT_SLIDE || !near_axis(m->jnt_axis + 3 * by, 0, 1, 0) ||
      m->jnt_type[byaw] != mjJNT_HINGE || !near_axis(m->jnt_axis + 3 * byaw, 0, 0, 1)) {
    throw InputError(pfile, "chains.base.joints",
                     "must be a slide joint along x, a slide joint along y and a hinge about z");
  }
  centre_base_on_start();

  // Every robot joint belongs to a chain, and has a position actuator.
  for (int j = 0; j < m->njnt; ++j) {
    if (!is_robot_body(m->jnt_bodyid[j])) continue;
    const char* name = mj_id2name(m, mjOBJ_JOINT, j);
    bool in_chain = false;
    for (const ChainIndex& c : chains_)
      in_chain = in_chain || std::count(c.joints.begin(), c.joints.end(), j);
    if (!in_chain) {
      throw InputError(pfile, "chains",
                       "robot joint '" + std::string(name ? name : "?") + "' is in no chain");
    }
    bool actuated = false;
    for (int a = 0; a < m->nu; ++a) {
      actuated =
          actuated || (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j &&
                       m->actuator_biastype[a] == mjBIAS_AFFINE);
    }
    if (!actuated) {
      throw InputError(mfile, "actuator",
                       "joint '" + std::string(name ? name : "?") + "' has no <position> actuator");
    }
  }

  for (const core::ChainSpec& spec : robot_.chains) {
    if (spec.end_effector.empty()) continue;
    try {
      frame(spec.end_effector);
    } catch (const std::out_of_range&) {
      throw InputError(
          pfile, "chains." + spec.name + ".end_effector",
          "frame '" + spec.end_effector + "' is neither a site nor a body in " + mfile);
    }
  }
  for (const core::HandSpec& hand : robot_.hands) {
    try {
      frame(hand.palm);
    } catch (const std::out_of_range&) {
      throw InputError(pfile, "hands." + hand.side + ".palm",
                       "frame '" + hand.palm + "' is neither a site nor a body in " + mfile);
    }
    for (const core::FingerSpec& finger : hand.fingers) {
      for (const std::string& body : finger.bodies) {
        if (mj_name2id(m, mjOBJ_BODY, body.c_str()) < 0) {
          throw InputError(pfile, "hands." + hand.side + ".fingers",
                           "body '" + body + "' is not in " + mfile);
        }
      }
    }
  }
  hand_of_body_.assign(m->nbody, -1);
  for (size_t h = 0; h < robot_.hands.size(); ++h) {
    const FrameRef palm = frame(robot_.hands[h].palm);
    const int palm_body = palm.kind == FrameRef::Kind::kSite ? m->site_bodyid[palm.id] : palm.id;
    for (int b = palm_body; b < m->nbody; ++b) {
      int up = b;
      while (up > palm_body) up = m->body_parentid[up];
      if (up == palm_body) hand_of_body_[b] = static_cast<int>(h);
    }
  }
  head_camera_ = mj_name2id(m, mjOBJ_CAMERA, robot_.head_camera.name.c_str());
  if (head_camera_ < 0 || !is_robot_body(m->cam_bodyid[head_camera_])) {
    throw InputError(pfile, "head_camera",
                     "camera '" + robot_.head_camera.name + "' is not a camera of the robot");
  }

  // Postures, their mirror images and canned keyframes within limits.
  auto check_limits = [&](const std::string& chain_name, const double* values,
                          const std::string& key) {
    const ChainIndex& c = chain(chain_name);
    for (size_t i = 0; i < c.joints.size(); ++i) {
      if (values[i] < c.lower[i] - core::kLimitRounding ||
          values[i] > c.upper[i] + core::kLimitRounding) {
        throw InputError(pfile, key,
                         "value " + std::to_string(values[i]) + " for joint '" +
                             mj_id2name(m, mjOBJ_JOINT, c.joints[i]) + "' is outside [" +
                             std::to_string(c.lower[i]) + ", " + std::to_string(c.upper[i]) + "]");
      }
    }
  };
  for (const auto& [posture_name, posture] : robot_.postures) {
    for (const auto& [chain_name, values] : posture) {
      const std::string key = "postures." + posture_name + "." + chain_name;
      check_limits(chain_name, values.data(), key);
      const std::string other = core::mirror_chain(chain_name);
      if (other.empty()) continue;
      const std::vector<double>& signs = robot_.mirror_signs.at(core::chain_kind(chain_name));
      std::vector<double> mirrored(values.size());
      for (size_t i = 0; i < values.size(); ++i) mirrored[i] = signs[i] * values[i];
      check_limits(other, mirrored.data(), key + " (mirrored to " + other + ")");
    }
  }
  for (const auto& [motion_name, motion] : robot_.canned) {
    for (size_t k = 0; k < motion.keyframes.size(); ++k) {
      size_t offset = 0;
      for (const std::string& chain_name : motion.chains) {
        const std::string key = "canned." + motion_name + ".keyframes[" + std::to_string(k) + "]";
        const double* values = motion.keyframes[k].values.data() + offset;
        check_limits(chain_name, values, key);
        const std::string other = core::mirror_chain(chain_name);
        if (!other.empty()) {
          const std::vector<double>& signs = robot_.mirror_signs.at(core::chain_kind(chain_name));
          std::vector<double> mirrored(signs.size());
          for (size_t i = 0; i < signs.size(); ++i) mirrored[i] = signs[i] * values[i];
          check_limits(other, mirrored.data(), key + " (mirrored to " + other + ")");
        }
        offset += chain(chain_name).joints.size();
      }
    }
  }

  // Environment names.
  DataPtr d = make_data(m);
  mj_forward(m, d.get());
  // Footprint of a body and its descendants (the bounding spheres of their geoms).
  auto footprint_of_body = [&](int body, const std::string& key) {
    core::Rect2 r{1e9, -1e9, 1e9, -1e9};
    bool any = false;
    for (int g = 0; g < m->ngeom; ++g) {
      int b = m->geom_bodyid[g];
      while (b > 0 && b != body) b = m->body_parentid[b];
      if (b != body) continue;
      any = true;
      const double x = d->geom_xpos[3 * g], y = d->geom_xpos[3 * g + 1], rb = m->geom_rbound[g];
      r = {std::min(r.x_min, x - rb), std::max(r.x_max, x + rb), std::min(r.y_min, y - rb),
           std::max(r.y_max, y + rb)};
    }
    if (!any)
      throw InputError(efile, key,
                       "body '" + std::string(mj_id2name(m, mjOBJ_BODY, body)) + "' has no geoms");
    return r;
  };
  for (const auto& [obj_name, obj] : environment_.objects) {
    for (const std::string& body : obj.bodies) {
      const int b = mj_name2id(m, mjOBJ_BODY, body.c_str());
      if (b < 0) {
        throw InputError(efile, "objects." + obj_name,
                         "body '" + body + "' is not in " + environment_.model_file.string());
      }
      if (obj.kind != core::ObjectKind::kSurface) {
        object_footprints_.push_back(footprint_of_body(b, "objects." + obj_name));
        object_footprint_bodies_.push_back(b);
      }
    }
    for (const std::string* site : {&obj.tip_site, &obj.grip_site}) {
      if (!site->empty() && mj_name2id(m, mjOBJ_SITE, site->c_str()) < 0) {
        throw InputError(efile, "objects." + obj_name,
                         "site '" + *site + "' is not in " + environment_.model_file.string());
      }
    }
  }
  if (!environment_.visitor.body.empty()) {
    const int b = mj_name2id(m, mjOBJ_BODY, environment_.visitor.body.c_str());
    if (b < 0)
      throw InputError(efile, "visitor.body",
                       "body '" + environment_.visitor.body + "' is missing");
    object_footprints_.push_back(footprint_of_body(b, "visitor.body"));
    object_footprint_bodies_.push_back(b);
    const Eigen::Vector2d axis(d->xpos[3 * b], d->xpos[3 * b + 1]);
    for (int g = 0; g < m->ngeom; ++g) {
      int up = m->geom_bodyid[g];
      while (up > 0 && up != b) up = m->body_parentid[up];
      if (up != b) continue;
      const Eigen::Vector2d at(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1]);
      visitor_radius_ = std::max(
          visitor_radius_, (at - axis).norm() + horizontal_half_extent(m, d.get(), g).maxCoeff());
    }
  }
  for (const std::string& cam : environment_.cameras) {
    if (mj_name2id(m, mjOBJ_CAMERA, cam.c_str()) < 0) {
      throw InputError(efile, "cameras",
                       "camera '" + cam + "' is not in " + environment_.model_file.string());
    }
  }
  for (int slot = 0; slot < environment_.obstacle_slots; ++slot) {
    ObstacleSlot s;
    s.body = mj_name2id(m, mjOBJ_BODY, obstacle_body_name(slot).c_str());
    for (int k = 0; k < 3; ++k) {
      s.geoms[k] =
          mj_name2id(m, mjOBJ_GEOM, obstacle_geom_name(slot, core::ObstacleShape(k)).c_str());
    }
    obstacle_slots_.push_back(s);
  }

  if (m->npair > 0) {
    throw InputError(mfile + " in " + environment_.model_file.string(), "contact.pair",
                     "explicit <contact><pair> elements are not supported");
  }
  ever_collides_.assign(m->ngeom, 0);
  for (int g = 0; g < m->ngeom; ++g)
    ever_collides_[g] = m->geom_contype[g] || m->geom_conaffinity[g];
  for (const ObstacleSlot& s : obstacle_slots_) {
    for (int g : s.geoms) ever_collides_[g] = 1;
  }
  for (int g1 = 0; g1 < m->ngeom; ++g1) {
    for (int g2 = g1 + 1; g2 < m->ngeom; ++g2) {
      if (!is_robot_geom(g1) && !is_robot_geom(g2)) continue;
      if (same_hand(m->geom_bodyid[g1], m->geom_bodyid[g2])) continue;
      if (auto p = collidable_pair(g1, g2)) robot_geom_pairs_.push_back(*p);
    }
  }

  start_qpos_.assign(m->qpos0, m->qpos0 + m->nq);
  start_qpos_[base.qpos_adr[0]] = environment_.robot_start.x;
  start_qpos_[base.qpos_adr[1]] = environment_.robot_start.y;
  start_qpos_[base.qpos_adr[2]] = environment_.robot_start.yaw;
  apply_posture("rest", start_qpos_.data());
  check_head_camera(*this, pfile);
  index_variations();
}

std::optional<GeomPair> Scene::collidable_pair(int g1, int g2) const {
  const mjModel* m = model_.get();
  if (g1 == g2 || !ever_collides_[g1] || !ever_collides_[g2]) return std::nullopt;
  const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
  if (body_pair_filtered(m, b1, b2) || excluded(m, b1, b2)) return std::nullopt;
  GeomPair p{g1, g2, std::max(m->geom_margin[g1], m->geom_margin[g2])};
  if (m->geom_type[p.g1] > m->geom_type[p.g2]) std::swap(p.g1, p.g2);
  return p;
}

void Scene::centre_base_on_start() {
  // A planar base's ranges say how far the robot may travel and turn from where it stands, not
  // where the room's origin is: each is shifted, its width kept, to centre on the room's start
  // pose, the yaw's only if it spans a full turn (a room whose start heading is near pi, facing
  // -x, would leave the robot a few degrees to turn one way). The base's actuators' control
  // ranges move with them. A start heading outside a yaw range narrower than a full turn is the
  // environment's error.
  mjModel* m = model_.get();
  ChainIndex& base = *std::find_if(chains_.begin(), chains_.end(),
                                   [](const ChainIndex& c) { return c.name == "base"; });
  const double start[3] = {environment_.robot_start.x, environment_.robot_start.y,
                           environment_.robot_start.yaw};
  for (int k = 0; k < 3; ++k) {
    const int j = base.joints[static_cast<size_t>(k)];
    const double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
    if (k == 2 && hi - lo < 2 * M_PI - kFullTurnSlackRad) {
      if (start[k] < lo || start[k] > hi) {
        throw InputError(environment_.spec_file.string(), "robot_start.yaw",
                         std::to_string(start[k]) + " is outside " + robot_.name +
                             "'s base yaw range [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "]");
      }
      continue;
    }
    const double shift = start[k] - 0.5 * (lo + hi);
    if (shift == 0) continue;
    m->jnt_range[2 * j] += shift;
    m->jnt_range[2 * j + 1] += shift;
    base.lower[static_cast<size_t>(k)] += shift;
    base.upper[static_cast<size_t>(k)] += shift;
    for (int a = 0; a < m->nu; ++a) {
      if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j &&
          m->actuator_ctrllimited[a]) {
        m->actuator_ctrlrange[2 * a] += shift;
        m->actuator_ctrlrange[2 * a + 1] += shift;
      }
    }
  }
}

const ChainIndex& Scene::chain(std::string_view name) const {
  for (const ChainIndex& c : chains_) {
    if (c.name == name) return c;
  }
  throw std::out_of_range("no chain '" + std::string(name) + "' in robot " + robot_.name);
}

FrameRef Scene::frame(std::string_view name) const {
  const std::string n(name);
  if (int s = mj_name2id(model_.get(), mjOBJ_SITE, n.c_str()); s >= 0)
    return {FrameRef::Kind::kSite, s};
  if (int b = mj_name2id(model_.get(), mjOBJ_BODY, n.c_str()); b >= 0)
    return {FrameRef::Kind::kBody, b};
  if (int c = mj_name2id(model_.get(), mjOBJ_CAMERA, n.c_str()); c >= 0)
    return {FrameRef::Kind::kCamera, c};
  // Objects by symbolic name, and their named frames.
  const size_t dot = n.find('.');
  const auto object = environment_.objects.find(n.substr(0, dot));
  if (object != environment_.objects.end() && !object->second.bodies.empty()) {
    const core::ObjectSpec& o = object->second;
    const std::string part = dot == std::string::npos ? "" : n.substr(dot + 1);
    const std::string* site = part == "tip" ? &o.tip_site : part == "grip" ? &o.grip_site : nullptr;
    if (part.empty()) return frame(o.bodies.front());
    if (site && !site->empty()) return frame(*site);
  }
  throw std::out_of_range("no frame '" + n + "' in robot " + robot_.name + " or environment " +
                          environment_.name);
}

bool Scene::is_robot_body(int body) const {
  return body > 0 && model_->body_rootid[body] == robot_root_;
}

bool Scene::is_robot_geom(int geom) const { return is_robot_body(model_->geom_bodyid[geom]); }

int Scene::hand_of_body(int body) const {
  return body >= 0 && body < static_cast<int>(hand_of_body_.size()) ? hand_of_body_[body] : -1;
}

bool Scene::same_hand(int body1, int body2) const {
  const int h = hand_of_body(body1);
  return h >= 0 && h == hand_of_body(body2);
}

void Scene::apply_posture(std::string_view posture, double* qpos) const {
  const auto it = robot_.postures.find(std::string(posture));
  if (it == robot_.postures.end()) {
    throw std::out_of_range("robot " + robot_.name + " has no posture '" + std::string(posture) +
                            "'");
  }
  for (const auto& [chain_name, values] : it->second) {
    const ChainIndex& c = chain(chain_name);
    for (size_t i = 0; i < values.size(); ++i) qpos[c.qpos_adr[i]] = values[i];
  }
}

core::LayoutRequest Scene::layout_request(int count) const {
  if (count > environment_.obstacle_slots) {
    throw InputError(environment_.spec_file.string(), "obstacle_slots",
                     std::to_string(count) + " obstacles requested but the environment reserves " +
                         std::to_string(environment_.obstacle_slots) + " slots");
  }
  core::LayoutRequest req;
  req.count = count;
  req.regions = environment_.obstacle_regions;
  req.protected_disks.push_back(
      {environment_.robot_start.x, environment_.robot_start.y, environment_.start_clearance_m});
  req.protected_rects = environment_.keep_out;
  req.protected_rects.insert(req.protected_rects.end(), object_footprints_.begin(),
                             object_footprints_.end());
  return req;
}

core::LayoutRequest Scene::layout_request(const core::ObstacleOptions& options) const {
  core::LayoutRequest req = layout_request(options.count);
  if (!options.regions.empty()) {
    std::vector<core::ObstacleRegion> chosen;
    for (const std::string& name : options.regions) {
      const auto it = std::find_if(req.regions.begin(), req.regions.end(),
                                   [&](const core::ObstacleRegion& r) { return r.name == name; });
      if (it == req.regions.end()) {
        std::string known;
        for (const core::ObstacleRegion& r : req.regions)
          known += (known.empty() ? "" : ", ") + r.name;
        throw InputError(environment_.spec_file.string(), "obstacle_regions",
                         "no region '" + name + "' (known: " + known + ")");
      }
      chosen.push_back(*it);
    }
    req.regions = std::move(chosen);
  }
  req.shapes = options.shapes;
  req.footprint_min_m = options.footprint_min_m;
  req.footprint_max_m = options.footprint_max_m;
  req.half_height_min_m = options.half_height_min_m;
  req.half_height_max_m = options.half_height_max_m;
  return req;
}

core::ObstacleLayout Scene::make_layout(const core::ObstacleOptions& options,
                                        std::uint64_t seed) const {
  const core::LayoutRequest request = layout_request(options);
  try {
    return core::generate_layout(request, seed);
  } catch (const core::LayoutError& e) {
    throw InputError(environment_.spec_file.string(), "obstacle_regions", e.what());
  }
}

core::ObstacleLayout Scene::make_layout(int count, std::uint64_t seed) const {
  const core::LayoutRequest request = layout_request(count);
  try {
    return core::generate_layout(request, seed);
  } catch (const core::LayoutError& e) {
    throw InputError(environment_.spec_file.string(), "obstacle_regions", e.what());
  }
}

// ---------------------------------------------------------------------------------------

WorkerScene::WorkerScene(std::shared_ptr<const Scene> scene)
    : scene_(std::move(scene)),
      model_(copy_model(scene_->model())),
      data_(make_data(model_.get())),
      start_qpos_(scene_->start_qpos()) {
  reset_to_start();
}

void WorkerScene::reset_to_start() {
  mj_resetData(model_.get(), data_.get());
  std::copy(start_qpos_.begin(), start_qpos_.end(), data_->qpos);
  mj_forward(model_.get(), data_.get());
}

std::vector<RobotContact> WorkerScene::robot_contacts() const {
  std::vector<RobotContact> out;
  const mjModel* m = model_.get();
  auto name = [&](mjtObj type, int id) {
    const char* n = mj_id2name(m, type, id);
    return n ? std::string(n) : "#" + std::to_string(id);
  };
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    if (!scene_->is_robot_geom(c.geom1) && !scene_->is_robot_geom(c.geom2)) continue;
    out.push_back({name(mjOBJ_GEOM, c.geom1), name(mjOBJ_BODY, m->geom_bodyid[c.geom1]),
                   name(mjOBJ_GEOM, c.geom2), name(mjOBJ_BODY, m->geom_bodyid[c.geom2]), c.dist});
  }
  return out;
}

}  // namespace taskmatrix::mujoco
