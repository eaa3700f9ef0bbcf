#include "taskmatrix/mujoco/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/mjcf_compose.h"
#include "taskmatrix/mujoco/mujoco_handles.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using test::RobotEnv;

TEST(ModelCatalog, HasTheBuiltInHumanoidsAndEnvironments) {
  // The project's own models (a TASKMATRIX_ROOT of a user's may hold others).
  const harness::ModelCatalog project(TASKMATRIX_TEST_ROOT);
  const auto robots = project.robots();
  const auto envs = project.environments();
  for (const char* name : {"tallbot", "minibot", "minibot_urdf", "atlas"}) {
    EXPECT_NE(std::find(robots.begin(), robots.end(), name), robots.end()) << name;
  }
  for (const char* name : {"kitchen", "office"}) {
    EXPECT_NE(std::find(envs.begin(), envs.end(), name), envs.end()) << name;
  }
}

class EveryRobotInEveryEnvironment : public ::testing::TestWithParam<RobotEnv> {};

TEST_P(EveryRobotInEveryEnvironment, LoadsAndTouchesNothingAtRest) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  const auto contacts = worker.robot_contacts();
  for (const RobotContact& c : contacts) {
    ADD_FAILURE() << c.body1 << "/" << c.geom1 << " touches " << c.body2 << "/" << c.geom2
                  << " at distance " << c.distance;
  }
  // Standing where the environment says, upright: the head camera is above the floor and the
  // robot's top is near its declared height.
  const mjModel* m = worker.model();
  const mjData* d = worker.data();
  double top = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (scene->is_robot_geom(g)) top = std::max(top, d->geom_xpos[3 * g + 2] + m->geom_rbound[g]);
  }
  EXPECT_NEAR(top, scene->robot().height_m, 0.08) << "top of the robot's bounding spheres";
  EXPECT_GT(d->cam_xpos[3 * scene->head_camera() + 2], 0.6 * scene->robot().height_m);
}

// Every posture touches nothing at the start pose; in `fist` (fingers closing on nothing)
// the fingers and palm of one hand may touch each other, and nothing else.
TEST_P(EveryRobotInEveryEnvironment, EveryPostureIsCollisionFree) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  const mjModel* m = scene->model();
  std::set<std::string> hand_bodies;  // finger segments and the palm's body, per side
  std::map<std::string, std::string> side_of;
  for (const core::HandSpec& hand : scene->robot().hands) {
    const FrameRef palm = scene->frame(hand.palm);
    const int palm_body = palm.kind == FrameRef::Kind::kSite ? m->site_bodyid[palm.id] : palm.id;
    side_of[mj_id2name(m, mjOBJ_BODY, palm_body)] = hand.side;
    for (const core::FingerSpec& f : hand.fingers) {
      for (const std::string& b : f.bodies) side_of[b] = hand.side;
    }
  }
  for (const auto& [name, posture] : scene->robot().postures) {
    std::vector<double> q = scene->start_qpos();
    scene->apply_posture(name, q.data());
    std::copy(q.begin(), q.end(), worker.data()->qpos);
    mj_forward(worker.model(), worker.data());
    for (const RobotContact& c : worker.robot_contacts()) {
      const auto s1 = side_of.find(c.body1), s2 = side_of.find(c.body2);
      const bool within_a_hand =
          s1 != side_of.end() && s2 != side_of.end() && s1->second == s2->second;
      if (name == "fist" && within_a_hand) continue;
      ADD_FAILURE() << "posture " << name << ": " << c.body1 << "/" << c.geom1 << " touches "
                    << c.body2 << "/" << c.geom2 << " at distance " << c.distance;
    }
  }
}

TEST_P(EveryRobotInEveryEnvironment, ProfileMatchesTheModel) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  const mjModel* m = scene->model();
  std::set<int> seen;
  int robot_joints = 0;
  for (int j = 0; j < m->njnt; ++j) robot_joints += scene->is_robot_body(m->jnt_bodyid[j]);
  for (const ChainIndex& c : scene->chains()) {
    for (size_t i = 0; i < c.joints.size(); ++i) {
      EXPECT_TRUE(seen.insert(c.joints[i]).second) << "joint in two chains: " << c.name;
      EXPECT_TRUE(std::isfinite(c.lower[i]) && std::isfinite(c.upper[i]));
      EXPECT_LT(c.lower[i], c.upper[i]);
      EXPECT_TRUE(scene->is_robot_body(m->jnt_bodyid[c.joints[i]]));
    }
  }
  EXPECT_EQ(static_cast<int>(seen.size()), robot_joints)
      << "every robot joint is in exactly one chain";
  // Limbs come in mirrored pairs: the same number of joints on both sides, and hands with
  // the same fingers (mirror_signs map one side's postures onto the other).
  for (const char* kind : {"arm", "hand"}) {
    EXPECT_EQ(scene->chain(std::string("left_") + kind).joints.size(),
              scene->chain(std::string("right_") + kind).joints.size())
        << kind;
  }
  const core::HandSpec* left = scene->robot().find_hand("left");
  const core::HandSpec* right = scene->robot().find_hand("right");
  ASSERT_EQ(left->fingers.size(), right->fingers.size());
  for (size_t f = 0; f < left->fingers.size(); ++f) {
    EXPECT_EQ(left->fingers[f].joints.size(), right->fingers[f].joints.size()) << "finger " << f;
  }
  // Environment objects the twelve programs need.
  const auto& objects = scene->environment().objects;
  for (const char* name : {"cup", "box", "vacuum", "debris"}) {
    EXPECT_TRUE(objects.count(name)) << name;
  }
  EXPECT_FALSE(scene->environment().visitor.body.empty());
  EXPECT_GE(scene->environment().visitor.path.size(), 2u);
}

// The geoms an environment places directly in the world (floor, walls, window) stand on static
// bodies of their own in the composed model, one geom each, where the file put them.
TEST_P(EveryRobotInEveryEnvironment, TheWorldsOwnGeomsStandOnStaticBodiesOfTheirOwn) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  const mjModel* m = scene->model();
  EXPECT_EQ(m->body_geomnum[0], 0) << "geoms left on the world body";
  char error[500] = "";
  mjModel* alone = mj_loadXML(scene->environment().model_file.c_str(), nullptr, error, 500);
  ASSERT_NE(alone, nullptr) << error;
  mjData* d_alone = mj_makeData(alone);
  mj_kinematics(alone, d_alone);
  WorkerScene worker(scene);
  const mjData* d = worker.data();
  int checked = 0;
  for (int g = 0; g < alone->body_geomnum[0]; ++g) {
    const int ga = alone->body_geomadr[0] + g;
    const char* name = mj_id2name(alone, mjOBJ_GEOM, ga);
    if (!name) continue;  // found again by name only
    const int gc = mj_name2id(m, mjOBJ_GEOM, name);
    ASSERT_GE(gc, 0) << name;
    const int b = m->geom_bodyid[gc];
    EXPECT_NE(b, 0) << name;
    EXPECT_EQ(m->body_weldid[b], 0) << name << " is not static";
    EXPECT_EQ(m->body_geomnum[b], 1) << name;
    // Named as the geom, so that a contact with it names it (never "body 3").
    const char* body = mj_id2name(m, mjOBJ_BODY, b);
    EXPECT_STREQ(body ? body : "", name);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(d->geom_xpos[3 * gc + i], d_alone->geom_xpos[3 * ga + i], 1e-12) << name;
    }
    for (int i = 0; i < 9; ++i) {
      EXPECT_NEAR(d->geom_xmat[9 * gc + i], d_alone->geom_xmat[9 * ga + i], 1e-12) << name;
    }
    EXPECT_EQ(m->geom_contype[gc], alone->geom_contype[ga]) << name;
    EXPECT_EQ(m->geom_conaffinity[gc], alone->geom_conaffinity[ga]) << name;
    ++checked;
  }
  EXPECT_GE(checked, 1) << "no named geom in the world of " << GetParam().environment;
  mj_deleteData(d_alone);
  mj_deleteModel(alone);
}

INSTANTIATE_TEST_SUITE_P(Models, EveryRobotInEveryEnvironment,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

TEST(Robots, TheTwoHumanoidsDifferAsInThePaper) {
  auto tall = test::scene("tallbot", "kitchen");
  auto compact = test::scene("minibot", "kitchen");
  EXPECT_GE(tall->robot().height_m, 1.6);
  EXPECT_LE(tall->robot().height_m, 1.8);
  EXPECT_GE(compact->robot().height_m, 1.0);
  EXPECT_LE(compact->robot().height_m, 1.2);
  EXPECT_EQ(tall->robot().find_hand("left")->fingers.size(), 3u);
  EXPECT_EQ(compact->robot().find_hand("left")->fingers.size(), 2u);
  EXPECT_EQ(tall->chain("head").joints.size(), 2u);
  EXPECT_GE(compact->chain("head").joints.size(), 1u);
  // Different names: no joint name is shared.
  for (const ChainIndex& c : tall->chains()) {
    for (int j : c.joints) {
      EXPECT_LT(
          mj_name2id(compact->model(), mjOBJ_JOINT, mj_id2name(tall->model(), mjOBJ_JOINT, j)), 0);
    }
  }
}

// The third built-in humanoid differs from both others in height, arm joints, hand and
// neck (models/README.md).
TEST(Robots, AtlasDiffersFromBothInHeightArmsHandAndNeck) {
  auto atlas = test::scene("atlas", "kitchen");
  EXPECT_NEAR(atlas->robot().height_m, 1.88, 0.01);  // Atlas (2013): 1.88 m
  EXPECT_EQ(atlas->chain("left_arm").joints.size(), 6u);
  EXPECT_EQ(atlas->chain("torso").joints.size(), 3u);
  const core::HandSpec* hand = atlas->robot().find_hand("left");
  EXPECT_EQ(hand->fingers.size(), 3u);
  for (const core::FingerSpec& f : hand->fingers) EXPECT_EQ(f.joints.size(), 3u);
  // A 1-DOF neck that pitches (minibot's turns): its axis is horizontal.
  ASSERT_EQ(atlas->chain("head").joints.size(), 1u);
  const mjtNum* axis = atlas->model()->jnt_axis + 3 * atlas->chain("head").joints[0];
  EXPECT_NEAR(axis[2], 0.0, 1e-9);
  for (const char* other : {"tallbot", "minibot"}) {
    auto s = test::scene(other, "kitchen");
    EXPECT_GT(std::abs(s->robot().height_m - atlas->robot().height_m), 0.1) << other;
    EXPECT_NE(s->chain("left_arm").joints.size(), 6u) << other;
    EXPECT_NE(s->robot().find_hand("left")->fingers[0].joints.size(), 3u) << other;
  }
}

TEST(Robots, EveryJointHasAPositionActuatorWithItsRange) {
  for (const std::string& robot : test::catalog().robots()) {
    auto scene = test::scene(robot, "kitchen");
    const mjModel* m = scene->model();
    for (const ChainIndex& c : scene->chains()) {
      for (size_t i = 0; i < c.joints.size(); ++i) {
        int found = 0;
        for (int a = 0; a < m->nu; ++a) {
          if (m->actuator_trnid[2 * a] != c.joints[i] || m->actuator_trntype[a] != mjTRN_JOINT)
            continue;
          ++found;
          EXPECT_EQ(m->actuator_biastype[a], mjBIAS_AFFINE) << robot << " position servo";
          EXPECT_GT(m->actuator_gainprm[a * mjNGAIN], 0) << robot;
          EXPECT_NEAR(m->actuator_ctrlrange[2 * a], c.lower[i], 1e-6) << robot;
          EXPECT_NEAR(m->actuator_ctrlrange[2 * a + 1], c.upper[i], 1e-6) << robot;
        }
        EXPECT_EQ(found, 1) << robot << " joint " << mj_id2name(m, mjOBJ_JOINT, c.joints[i]);
      }
    }
  }
}

// A binary STL of a 4 x 3 x 2 cm box centred on its origin.
void write_box_stl(const std::filesystem::path& file) {
  std::filesystem::create_directories(file.parent_path());
  const float v[8][3] = {{-.02f, -.015f, -.01f}, {-.02f, -.015f, .01f}, {-.02f, .015f, -.01f},
                         {-.02f, .015f, .01f},   {.02f, -.015f, -.01f}, {.02f, -.015f, .01f},
                         {.02f, .015f, -.01f},   {.02f, .015f, .01f}};
  const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                            {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  std::ofstream out(file, std::ios::binary);
  const char header[80] = {};
  out.write(header, sizeof header);
  const std::uint32_t n = 12;
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  for (const auto& f : faces) {
    const float normal[3] = {0, 0, 0};
    out.write(reinterpret_cast<const char*>(normal), sizeof normal);
    for (int i : f) out.write(reinterpret_cast<const char*>(v[i]), sizeof v[i]);
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), sizeof attributes);
  }
}

// A copy of minibot (MJCF only) in the scratch root's robots, named `name`.
void copy_minibot(const test::ScratchRoot& root, const std::string& name) {
  const std::filesystem::path robots = root.path() / "models" / "robots";
  std::filesystem::copy(robots / "minibot", robots / name);
  std::filesystem::remove(robots / name / "minibot.urdf");
  root.replace("models/robots/" + name + "/profile.yaml", "name: minibot", "name: " + name);
}

// Public humanoid models come with mesh files beside them, named relative to the model's
// folder and its compiler's meshdir (MJCF), or as package:// URIs found through meshdir
// (URDF). The composed scene compiles from memory: the files must still be found, and the
// mesh collides as the robot's part.
TEST(Robots, MeshFilesAreFoundBesideTheRobotsModelMjcfAndUrdf) {
  test::ScratchRoot root;
  const std::filesystem::path robots = root.path() / "models" / "robots";
  const std::filesystem::path kitchen = root.path() / "models" / "environments" / "kitchen";
  // MJCF: meshdir="parts", the visor a colliding mesh on the head.
  copy_minibot(root, "meshy");
  write_box_stl(robots / "meshy" / "parts" / "visor.stl");
  const std::string xml = "models/robots/meshy/minibot.xml";
  root.replace(xml, "<compiler ", "<compiler meshdir=\"parts\" ");
  root.replace(xml, "<worldbody>",
               "<asset><mesh name=\"visor\" file=\"visor.stl\"/></asset>\n  <worldbody>");
  root.replace(xml, "<geom name=\"HeadSkull\"",
               "<geom name=\"Visor\" type=\"mesh\" mesh=\"visor\" pos=\"0.07 0 0.14\"/>"
               "<geom name=\"HeadSkull\"");
  auto mjcf = Scene::load(robots / "meshy", kitchen);
  const mjModel* m = mjcf->model();
  ASSERT_EQ(m->nmesh, 1);
  const int visor = mj_name2id(m, mjOBJ_GEOM, "Visor");
  ASSERT_GE(visor, 0);
  EXPECT_EQ(m->geom_type[visor], mjGEOM_MESH);
  EXPECT_NE(m->geom_contype[visor], 0);
  EXPECT_TRUE(mjcf->is_robot_body(m->geom_bodyid[visor]));
  // URDF: the mesh by a package:// URI, found through the URDF's <mujoco> meshdir.
  std::filesystem::create_directories(robots / "meshy_urdf");
  std::filesystem::copy(robots / "minibot" / "minibot.urdf", robots / "meshy_urdf" / "m.urdf");
  write_box_stl(robots / "meshy_urdf" / "meshes" / "visor.stl");
  root.write("models/robots/meshy_urdf/profile.yaml",
             root.read("models/robots/minibot_urdf/profile.yaml"));
  root.replace("models/robots/meshy_urdf/profile.yaml", "name: minibot_urdf", "name: meshy_urdf");
  root.replace("models/robots/meshy_urdf/profile.yaml", "urdf: ../minibot/minibot.urdf",
               "urdf: m.urdf");
  const std::string urdf = "models/robots/meshy_urdf/m.urdf";
  root.replace(urdf, "<compiler ", "<compiler meshdir=\"meshes\" ");
  root.replace(urdf, "    <collision name=\"HeadNeck\">",
               "    <collision name=\"Visor\"><origin xyz=\"0.07 0 0.14\" rpy=\"0 0 0\"/>"
               "<geometry><mesh filename=\"package://meshy/meshes/visor.stl\"/></geometry>"
               "</collision>\n    <collision name=\"HeadNeck\">");
  auto from_urdf = Scene::load(robots / "meshy_urdf", kitchen);
  EXPECT_EQ(from_urdf->model()->nmesh, 1);
}

// MJCF's default angle unit is degrees, and public models often leave it so. A robot file in
// degrees composes with a room in radians, and compiles to what MuJoCo makes of the file alone:
// orientations, hinge and ball ranges, a hinge's ref and springref, from its own attributes
// or from class defaults (a slide joint sharing them keeps its metres); an actuator's
// ctrlrange and a joint's margin stay as written, as MuJoCo leaves them; the <joint> elements
// of an equality and a fixed tendon name joints and are left alone.
TEST(Robots, AModelInDegreesComposesAsMuJoCoCompilesItAlone) {
  const std::string robot = R"(<mujoco model="deg">
  <compiler angle="degree" autolimits="true"/>
  <default>
    <joint range="-90 45" damping="1"/>
    <default class="arm"><joint ref="10" springref="20" range="-30 120"/></default>
    <default class="rail"><joint type="slide" range="0 0.4"/></default>
  </default>
  <worldbody>
    <body name="trunk" pos="3 3 1" euler="0 0 90" childclass="arm">
      <joint name="shoulder" axis="0 1 0"/>
      <joint name="elbow" class="main" axis="1 0 0" margin="5"/>
      <geom name="trunk_box" type="box" size="0.1 0.1 0.1" euler="10 20 30"/>
      <site name="tip" pos="0 0 0.2" axisangle="0 0 1 45"/>
      <body name="slider" pos="0 0 0.3">
        <joint name="lift" class="rail" axis="0 0 1"/>
        <geom name="slider_box" type="box" size="0.05 0.05 0.05"/>
        <body name="ball_link" pos="0 0 0.2" axisangle="1 0 0 30">
          <joint name="wrist" type="ball" range="0 60"/>
          <geom name="ball_geom" size="0.03"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><position name="shoulder" joint="shoulder" ctrlrange="-0.5 2"/></actuator>
  <equality><joint joint1="elbow" joint2="shoulder" polycoef="0 1 0 0 0"/></equality>
  <tendon><fixed name="pair"><joint joint="elbow" coef="1"/><joint joint="shoulder" coef="1"/></fixed></tendon>
</mujoco>
)";
  const std::filesystem::path env_file =
      test::catalog().root() / "models" / "environments" / "kitchen" / "kitchen.xml";
  std::ifstream in(env_file);
  const std::string env((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string scene =
      compose_scene_mjcf({robot, "deg.xml"}, {env, env_file.string()}, CompositionOptions{});
  ModelPtr composed = compile_mjcf_text(scene, "composed");
  ModelPtr alone = compile_mjcf_text(robot, "deg.xml");
  const mjModel* a = alone.get();
  const mjModel* c = composed.get();
  for (const char* name : {"shoulder", "elbow", "lift", "wrist"}) {
    const int ja = mj_name2id(a, mjOBJ_JOINT, name), jc = mj_name2id(c, mjOBJ_JOINT, name);
    ASSERT_GE(ja, 0);
    ASSERT_GE(jc, 0) << name;
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(c->jnt_range[2 * jc + k], a->jnt_range[2 * ja + k], 1e-12) << name;
    }
    EXPECT_NEAR(c->jnt_margin[jc], a->jnt_margin[ja], 1e-12) << name;
    const int qa = a->jnt_qposadr[ja], qc = c->jnt_qposadr[jc];
    EXPECT_NEAR(c->qpos0[qc], a->qpos0[qa], 1e-12) << name;
    EXPECT_NEAR(c->qpos_spring[qc], a->qpos_spring[qa], 1e-12) << name;
  }
  EXPECT_NEAR(c->jnt_range[2 * mj_name2id(c, mjOBJ_JOINT, "shoulder") + 1], 120 * M_PI / 180,
              1e-12);
  EXPECT_NEAR(c->jnt_range[2 * mj_name2id(c, mjOBJ_JOINT, "lift") + 1], 0.4, 1e-12);
  auto same_quat = [](const mjtNum* x, const mjtNum* y) {
    return std::abs(x[0] - y[0]) + std::abs(x[1] - y[1]) + std::abs(x[2] - y[2]) +
               std::abs(x[3] - y[3]) <
           1e-12;
  };
  for (const char* name : {"trunk", "ball_link"}) {
    const int ba = mj_name2id(a, mjOBJ_BODY, name), bc = mj_name2id(c, mjOBJ_BODY, name);
    ASSERT_GE(bc, 0) << name;
    EXPECT_TRUE(same_quat(c->body_quat + 4 * bc, a->body_quat + 4 * ba)) << name;
  }
  const int ga = mj_name2id(a, mjOBJ_GEOM, "trunk_box"),
            gc = mj_name2id(c, mjOBJ_GEOM, "trunk_box");
  EXPECT_TRUE(same_quat(c->geom_quat + 4 * gc, a->geom_quat + 4 * ga));
  const int sa = mj_name2id(a, mjOBJ_SITE, "tip"), sc = mj_name2id(c, mjOBJ_SITE, "tip");
  EXPECT_TRUE(same_quat(c->site_quat + 4 * sc, a->site_quat + 4 * sa));
  const int ua = mj_name2id(a, mjOBJ_ACTUATOR, "shoulder"),
            uc = mj_name2id(c, mjOBJ_ACTUATOR, "shoulder");
  EXPECT_EQ(c->actuator_ctrlrange[2 * uc + 1], a->actuator_ctrlrange[2 * ua + 1]);
  EXPECT_EQ(c->actuator_ctrlrange[2 * uc + 1], 2.0);
}

// Public models split their files (<include>) and store poses (<keyframe>): a minibot copy
// with its actuators in an included file and a "home" keyframe composes as minibot does; an
// include of a missing file names the including file and the key.
TEST(Robots, IncludedFilesAndKeyframesOfAPublicModelCompose) {
  test::ScratchRoot root;
  const std::filesystem::path robots = root.path() / "models" / "robots";
  const std::filesystem::path kitchen = root.path() / "models" / "environments" / "kitchen";
  copy_minibot(root, "split");
  const std::string xml = "models/robots/split/minibot.xml";
  const std::string text = root.read(xml);
  const size_t from = text.find("  <actuator>"), to = text.find("</actuator>");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  std::filesystem::create_directories(robots / "split" / "parts");
  root.write("models/robots/split/parts/actuators.xml",
             "<mujoco>\n" + text.substr(from, to + 11 - from) + "\n</mujoco>\n");
  root.write(xml, text.substr(0, from) +
                      "  <include file=\"parts/actuators.xml\"/>\n"
                      "  <keyframe><key name=\"home\" time=\"0\"/></keyframe>\n" +
                      text.substr(to + 11));
  auto split = Scene::load(robots / "split", kitchen);
  auto original = Scene::load(robots / "minibot", kitchen);
  EXPECT_EQ(split->model()->nu, original->model()->nu);
  EXPECT_GT(split->model()->nu, 20);
  EXPECT_EQ(split->model()->nkey, 0);
  root.replace(xml, "parts/actuators.xml", "parts/missing.xml");
  try {
    Scene::load(robots / "split", kitchen);
    ADD_FAILURE() << "an include of a missing file loaded";
  } catch (const core::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("minibot.xml"), std::string::npos) << what;
    EXPECT_NE(what.find("include"), std::string::npos) << what;
    EXPECT_NE(what.find("missing.xml"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace taskmatrix::mujoco
