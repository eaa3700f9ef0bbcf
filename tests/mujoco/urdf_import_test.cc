#include "taskmatrix/mujoco/urdf_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>

#include "taskmatrix/io/model_files.h"
#include "taskmatrix/mujoco/scene.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

// A URDF twin: a robot whose profile names a URDF file in another robot's folder, that
// robot being described by MJCF (minibot_urdf and minibot). The URDF is parsed by urdfdom,
// compiled by MuJoCo's URDF importer and completed from its profile; it must be the same
// robot as the MJCF twin. Every such pair under the models folder is tested.
struct TwinPair {
  std::string urdf, mjcf;
};
void PrintTo(const TwinPair& p, std::ostream* os) { *os << p.urdf << " and " << p.mjcf; }

std::vector<TwinPair> twin_pairs() {
  std::vector<TwinPair> out;
  const harness::ModelCatalog& catalog = test::catalog();
  for (const std::string& robot : catalog.robots()) {
    const core::RobotProfile p = io::load_robot_profile(catalog.robot_dir(robot) / "profile.yaml");
    if (p.format != core::ModelFormat::kUrdf) continue;
    const std::string folder = p.model_file.parent_path().filename().string();
    if (folder == robot) continue;
    const auto robots = catalog.robots();
    if (std::find(robots.begin(), robots.end(), folder) == robots.end()) continue;
    const core::RobotProfile twin =
        io::load_robot_profile(catalog.robot_dir(folder) / "profile.yaml");
    if (twin.format == core::ModelFormat::kMjcf) out.push_back({robot, folder});
  }
  return out;
}

class UrdfTwin : public ::testing::TestWithParam<TwinPair> {
 protected:
  std::shared_ptr<const Scene> urdf = test::scene(GetParam().urdf, "kitchen");
  std::shared_ptr<const Scene> mjcf = test::scene(GetParam().mjcf, "kitchen");
};

TEST_P(UrdfTwin, AgreesOnChainsJointsAndLimits) {
  ASSERT_EQ(urdf->chains().size(), mjcf->chains().size());
  for (const ChainIndex& u : urdf->chains()) {
    const ChainIndex& m = mjcf->chain(u.name);
    ASSERT_EQ(u.joints.size(), m.joints.size()) << u.name;
    for (size_t i = 0; i < u.joints.size(); ++i) {
      EXPECT_STREQ(mj_id2name(urdf->model(), mjOBJ_JOINT, u.joints[i]),
                   mj_id2name(mjcf->model(), mjOBJ_JOINT, m.joints[i]));
      EXPECT_EQ(urdf->model()->jnt_type[u.joints[i]], mjcf->model()->jnt_type[m.joints[i]]);
      EXPECT_NEAR(u.lower[i], m.lower[i], 1e-9) << u.name;
      EXPECT_NEAR(u.upper[i], m.upper[i], 1e-9) << u.name;
    }
  }
}

// A frame's pose in `d`: a site, else a body, else a camera of the model.
std::pair<const mjtNum*, const mjtNum*> frame_pose(const Scene& s, const mjData* d,
                                                   const std::string& name) {
  const FrameRef f = s.frame(name);
  switch (f.kind) {
    case FrameRef::Kind::kSite:
      return {d->site_xpos + 3 * f.id, d->site_xmat + 9 * f.id};
    case FrameRef::Kind::kBody:
      return {d->xpos + 3 * f.id, d->xmat + 9 * f.id};
    case FrameRef::Kind::kCamera:
      break;
  }
  return {d->cam_xpos + 3 * f.id, d->cam_xmat + 9 * f.id};
}

TEST_P(UrdfTwin, BodyPalmAndHeadCameraPosesAgreeAtRandomConfigurations) {
  WorkerScene wu(urdf), wm(mjcf);
  // Every robot body the two share by name (the URDF's links, the MJCF's bodies).
  std::vector<std::pair<int, int>> bodies;
  for (int bu = 1; bu < wu.model()->nbody; ++bu) {
    if (!urdf->is_robot_body(bu)) continue;
    const int bm = mj_name2id(wm.model(), mjOBJ_BODY, mj_id2name(wu.model(), mjOBJ_BODY, bu));
    if (bm >= 0) bodies.push_back({bu, bm});
  }
  EXPECT_GE(bodies.size(), urdf->chains().size());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> qu = urdf->start_qpos(), qm = mjcf->start_qpos();
    for (const ChainIndex& cu : urdf->chains()) {
      const ChainIndex& cm = mjcf->chain(cu.name);
      for (size_t i = 0; i < cu.joints.size(); ++i) {
        const double v = cu.lower[i] + (cu.upper[i] - cu.lower[i]) * unit(rng);
        qu[cu.qpos_adr[i]] = v;
        qm[cm.qpos_adr[i]] = v;
      }
    }
    std::copy(qu.begin(), qu.end(), wu.data()->qpos);
    std::copy(qm.begin(), qm.end(), wm.data()->qpos);
    mj_kinematics(wu.model(), wu.data());
    mj_kinematics(wm.model(), wm.data());
    mj_camlight(wu.model(), wu.data());
    mj_camlight(wm.model(), wm.data());
    for (const auto& [bu, bm] : bodies) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_NEAR(wu.data()->xpos[3 * bu + k], wm.data()->xpos[3 * bm + k], 1e-9)
            << mj_id2name(wu.model(), mjOBJ_BODY, bu);
      }
      for (int k = 0; k < 9; ++k) {
        ASSERT_NEAR(wu.data()->xmat[9 * bu + k], wm.data()->xmat[9 * bm + k], 1e-9)
            << mj_id2name(wu.model(), mjOBJ_BODY, bu);
      }
    }
    for (const core::HandSpec& hand : urdf->robot().hands) {
      const auto [pu, ru] = frame_pose(*urdf, wu.data(), hand.palm);
      const auto [pm, rm] = frame_pose(*mjcf, wm.data(), mjcf->robot().find_hand(hand.side)->palm);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(pu[k], pm[k], 1e-9) << hand.side << " palm";
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(ru[k], rm[k], 1e-9) << hand.side << " palm";
    }
    const int cu = urdf->head_camera(), cm = mjcf->head_camera();
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(wu.data()->cam_xpos[3 * cu + k], wm.data()->cam_xpos[3 * cm + k], 1e-9);
    for (int k = 0; k < 9; ++k)
      EXPECT_NEAR(wu.data()->cam_xmat[9 * cu + k], wm.data()->cam_xmat[9 * cm + k], 1e-6);
  }
}

TEST_P(UrdfTwin, ImporterAddsAnActuatorPerJointAndTheCamera) {
  const std::string mjcf_text = import_urdf_as_mjcf(urdf->robot());
  EXPECT_NE(mjcf_text.find("<camera name=\"" + urdf->robot().head_camera.name + "\""),
            std::string::npos);
  size_t actuators = 0;
  for (size_t at = 0; (at = mjcf_text.find("<position ", at)) != std::string::npos; ++at)
    ++actuators;
  size_t joints = 0;
  for (const ChainIndex& c : urdf->chains()) joints += c.joints.size();
  EXPECT_EQ(actuators, joints);
}

// The project's models hold one pair (minibot_urdf, minibot); a user's folder may hold none.
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(UrdfTwin);
INSTANTIATE_TEST_SUITE_P(Models, UrdfTwin, ::testing::ValuesIn(twin_pairs()),
                         [](const auto& p) { return p.param.urdf + "_and_" + p.param.mjcf; });

TEST(UrdfTwins, TheProjectHasMinibotAndItsUrdfTwin) {
  if (std::getenv("TASKMATRIX_ROOT")) GTEST_SKIP() << "TASKMATRIX_ROOT names other models";
  const std::vector<TwinPair> pairs = twin_pairs();
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].urdf, "minibot_urdf");
  EXPECT_EQ(pairs[0].mjcf, "minibot");
}

}  // namespace
}  // namespace taskmatrix::mujoco
