#include "taskmatrix/mujoco/urdf_import.h"

#include <gtest/gtest.h>

#include <random>

#include "taskmatrix/mujoco/scene.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

// minibot_urdf is minibot described as URDF: parsed by urdfdom, compiled by MuJoCo's URDF
// importer and completed from its profile. It must be the same robot as the MJCF twin.
class UrdfTwin : public ::testing::Test {
 protected:
  std::shared_ptr<const Scene> urdf = test::scene("minibot_urdf", "kitchen");
  std::shared_ptr<const Scene> mjcf = test::scene("minibot", "kitchen");
};

TEST_F(UrdfTwin, AgreesOnChainsJointsAndLimits) {
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

TEST_F(UrdfTwin, PalmAndHeadCameraPosesAgreeAtRandomConfigurations) {
  WorkerScene wu(urdf), wm(mjcf);
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
    for (const char* palm : {"LPalm", "RPalm"}) {
      const int bu = mj_name2id(wu.model(), mjOBJ_BODY, palm);
      const int bm = mj_name2id(wm.model(), mjOBJ_BODY, palm);
      ASSERT_GE(bu, 0);
      ASSERT_GE(bm, 0);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(wu.data()->xpos[3 * bu + k], wm.data()->xpos[3 * bm + k], 1e-9) << palm;
      }
      for (int k = 0; k < 9; ++k) {
        EXPECT_NEAR(wu.data()->xmat[9 * bu + k], wm.data()->xmat[9 * bm + k], 1e-9) << palm;
      }
    }
    const int cu = urdf->head_camera(), cm = mjcf->head_camera();
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(wu.data()->cam_xpos[3 * cu + k], wm.data()->cam_xpos[3 * cm + k], 1e-9);
    for (int k = 0; k < 9; ++k)
      EXPECT_NEAR(wu.data()->cam_xmat[9 * cu + k], wm.data()->cam_xmat[9 * cm + k], 1e-6);
  }
}

TEST_F(UrdfTwin, ImporterAddsAnActuatorPerJointAndTheCamera) {
  const std::string mjcf_text = import_urdf_as_mjcf(urdf->robot());
  EXPECT_NE(mjcf_text.find("<camera name=\"HeadCam\""), std::string::npos);
  size_t actuators = 0;
  for (size_t at = 0; (at = mjcf_text.find("<position ", at)) != std::string::npos; ++at)
    ++actuators;
  size_t joints = 0;
  for (const ChainIndex& c : urdf->chains()) joints += c.joints.size();
  EXPECT_EQ(actuators, joints);
}

}  // namespace
}  // namespace taskmatrix::mujoco
