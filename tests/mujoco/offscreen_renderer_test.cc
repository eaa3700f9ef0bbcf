#include "taskmatrix/mujoco/offscreen_renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "taskmatrix/mujoco/scene.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using test::RobotEnv;

class RenderEveryScene : public ::testing::TestWithParam<RobotEnv> {};

// The robot is visible: the overview image changes in a good share of its pixels when the
// robot's geoms are hidden.
TEST_P(RenderEveryScene, RobotIsVisibleInTheOverview) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  OffscreenRenderer renderer(scene->model(), 320, 240);
  CameraView view;
  ASSERT_FALSE(scene->environment().cameras.empty());
  view.fixed_camera =
      mj_name2id(scene->model(), mjOBJ_CAMERA, scene->environment().cameras[0].c_str());
  const RgbImage with_robot = renderer.render_rgb(worker.model(), worker.data(), view);
  for (int g = 0; g < worker.model()->ngeom; ++g) {
    if (scene->is_robot_geom(g)) worker.model()->geom_rgba[4 * g + 3] = 0;  // invisible
  }
  const RgbImage without_robot = renderer.render_rgb(worker.model(), worker.data(), view);
  ASSERT_EQ(with_robot.pixels.size(), 320u * 240u * 3u);
  int changed = 0;
  for (size_t p = 0; p < with_robot.pixels.size(); p += 3) {
    int diff = 0;
    for (int k = 0; k < 3; ++k)
      diff += std::abs(with_robot.pixels[p + k] - without_robot.pixels[p + k]);
    changed += diff > 30;
  }
  const double share = changed / (320.0 * 240.0);
  EXPECT_GT(share, 0.02) << "robot covers too little of the overview image";
  // Not a blank image either.
  int distinct_rows = 0;
  for (int y = 1; y < 240; ++y) {
    distinct_rows +=
        !std::equal(with_robot.pixels.begin() + (y - 1) * 960, with_robot.pixels.begin() + y * 960,
                    with_robot.pixels.begin() + y * 960);
  }
  EXPECT_GT(distinct_rows, 100);
}

// The head camera sees the work surface: depth is finite over most of the image, varies,
// and lies within the room.
TEST_P(RenderEveryScene, HeadCameraDepthSeesTheRoom) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  OffscreenRenderer renderer(scene->model(), 160, 120);
  CameraView head;
  head.fixed_camera = scene->head_camera();
  const DepthImage depth = renderer.render_depth(worker.model(), worker.data(), head);
  double lo = 1e9, hi = 0;
  int finite = 0;
  for (float v : depth.metres) {
    if (!std::isfinite(v)) continue;
    ++finite;
    lo = std::min<double>(lo, v);
    hi = std::max<double>(hi, v);
  }
  EXPECT_GT(finite, 160 * 120 * 9 / 10);
  EXPECT_GT(lo, 0.05);
  EXPECT_LT(hi, 12.0);
  EXPECT_GT(hi - lo, 0.5) << "depth does not vary";
}

INSTANTIATE_TEST_SUITE_P(Models, RenderEveryScene,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

TEST(OffscreenRenderer, RejectsASizeBeyondTheOffscreenBuffer) {
  auto scene = test::scene("minibot", "kitchen");
  EXPECT_THROW(OffscreenRenderer(scene->model(), 4000, 3000), std::runtime_error);
}

}  // namespace
}  // namespace taskmatrix::mujoco
