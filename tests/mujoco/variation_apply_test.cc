// Task variations written into a worker's model copy (WorkerScene::apply_variation): surfaces
// at a new height keep standing on the floor and carry what rests on them, nothing starts
// interpenetrating, the simulation leaves resting objects where they are, and the shared
// compiled model is never written.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "taskmatrix/core/task_variation.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "taskmatrix/mujoco/scene.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

class VariationInEveryScene : public ::testing::TestWithParam<test::RobotEnv> {};

int body_of(const mjModel* m, const Scene& scene, const std::string& object) {
  return mj_name2id(m, mjOBJ_BODY, scene.environment().objects.at(object).bodies.front().c_str());
}

double lowest_z(const mjModel* m, const mjData* d, int body) {
  return body_box(m, d, body, true).min().z();
}

TEST_P(VariationInEveryScene, SurfacesMoveWithWhatRestsOnThemAndPhysicsLeavesItThere) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  const mjModel* m0 = scene->model();
  const core::SurfaceGeometry& table = *scene->world_geometry().surface("work_surface");
  const int table_body = body_of(m0, *scene, "work_surface");
  for (const double height : {0.55, 0.80}) {
    SCOPED_TRACE("height " + std::to_string(height));
    core::TrialLayout layout;
    layout.variation.surfaces = {{"work_surface", height, height - table.height}};
    MujocoSkillset skills(scene);
    skills.apply_layout(layout);
    const mjModel* m = skills.model();
    const mjData* d = skills.sim_data();
    // The top face is at the drawn height; the furniture still stands on the floor.
    EXPECT_NEAR(surface_box(m, d, table_body).max().z(), height, 1e-9);
    EXPECT_NEAR(body_box(m, d, table_body, true).min().z(), 0.0, 1e-9);
    // What rested on it still does.
    for (const char* object : {"cup", "box", "vacuum"}) {
      EXPECT_NEAR(lowest_z(m, d, body_of(m, *scene, object)), height, 1e-6) << object;
    }
    for (const std::string& flake : scene->environment().objects.at("debris").bodies) {
      const int b = mj_name2id(m, mjOBJ_BODY, flake.c_str());
      EXPECT_NEAR(d->xpos[3 * b + 2] - m0->body_pos[3 * b + 2], height - table.height, 1e-12);
    }
    // No initial penetration anywhere.
    for (int i = 0; i < d->ncon; ++i) {
      ASSERT_GE(d->contact[i].dist, -1e-4)
          << mj_id2name(m, mjOBJ_GEOM, d->contact[i].geom1) << " in "
          << mj_id2name(m, mjOBJ_GEOM, d->contact[i].geom2);
    }
    // A second of simulation (the robot holding its start) leaves the objects where they are.
    std::map<std::string, Eigen::Vector3d> before;
    for (const char* object : {"cup", "box", "vacuum"}) {
      const int b = body_of(m, *scene, object);
      before[object] = Eigen::Vector3d(d->xpos + 3 * b);
    }
    for (int k = 0; k < 100; ++k) ASSERT_FALSE(skills.advance().unstable);
    for (const auto& [object, p] : before) {
      const int b = body_of(m, *scene, object);
      EXPECT_LT((Eigen::Vector3d(d->xpos + 3 * b) - p).norm(), 0.002) << object << " moved";
      EXPECT_GT(d->xmat[9 * b + 8], std::cos(1.0 * M_PI / 180)) << object << " tilted";
    }
  }
}

TEST_P(VariationInEveryScene, PlacedObjectsAndTheRobotStartWhereDrawnAndTheSharedModelStays) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  core::VariationOptions v;
  v.objects = {{"vacuum", "work_surface", {0, 1, 0, 1}, core::ValueRange{-0.5, 0.5}},
               {"cup", "work_surface", {0, 1, 0, 1}, core::ValueRange{-3.14, 3.14}},
               {"box", "work_surface", {0, 1, 0, 1}, core::ValueRange{-3.14, 3.14}}};
  v.surfaces = {{"work_surface", {0.55, 0.80}}};
  v.robot_start = core::RobotStartOptions{{-0.05, 0.05}, {-0.1, 0.1}, {-0.15, 0.15}};
  core::ObstacleOptions obstacles;
  obstacles.count = 8;
  core::TargetedObstacles near = core::targeted_defaults(core::TargetedObstacles::Kind::kNear);
  near.object = "cup";
  near.count = 4;
  near.radius_m = 0.3;
  obstacles.targeted = {near};
  const std::vector<double> shared_size(scene->model()->geom_size,
                                        scene->model()->geom_size + 3 * scene->model()->ngeom);
  WorkerScene worker(scene);
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const core::TrialLayout layout = scene->make_trial_layout(obstacles, v, seed);
    worker.apply(layout);
    worker.reset_to_start();
    const mjModel* m = worker.model();
    const mjData* d = worker.data();
    for (const core::ObjectDraw& o : layout.variation.objects) {
      const int b = body_of(m, *scene, o.object);
      EXPECT_NEAR(d->xpos[3 * b], o.x, 1e-9);
      EXPECT_NEAR(d->xpos[3 * b + 1], o.y, 1e-9);
      // Just above the surface at its drawn height (core::kRestGapM), to settle onto it.
      EXPECT_NEAR(lowest_z(m, d, b), layout.variation.surfaces[0].height_m + core::kRestGapM, 1e-6);
    }
    const ChainIndex& base = scene->chain("base");
    EXPECT_EQ(d->qpos[base.qpos_adr[2]], layout.variation.robot_start->yaw);
    // MuJoCo's own collision detection: nothing touches the robot, nothing interpenetrates.
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& c = d->contact[i];
      ASSERT_FALSE(scene->is_robot_geom(c.geom1) || scene->is_robot_geom(c.geom2))
          << mj_id2name(m, mjOBJ_GEOM, c.geom1) << " touches "
          << mj_id2name(m, mjOBJ_GEOM, c.geom2);
      ASSERT_GE(c.dist, -1e-4) << mj_id2name(m, mjOBJ_GEOM, c.geom1) << " in "
                               << mj_id2name(m, mjOBJ_GEOM, c.geom2);
    }
  }
  worker.apply(core::TrialLayout{});  // nothing varied: the model as compiled (but the
  std::set<int> slot_geoms;           // obstacle slots, which keep their last sizes, disabled)
  for (const ObstacleSlot& s : scene->obstacle_slots())
    slot_geoms.insert(s.geoms.begin(), s.geoms.end());
  for (int i = 0; i < 3 * scene->model()->ngeom; ++i) {
    ASSERT_EQ(scene->model()->geom_size[i], shared_size[static_cast<size_t>(i)]);
    if (slot_geoms.count(i / 3)) continue;
    ASSERT_EQ(worker.model()->geom_size[i], scene->model()->geom_size[i]);
    ASSERT_EQ(worker.model()->geom_pos[i], scene->model()->geom_pos[i]);
  }
}

TEST_P(VariationInEveryScene, AHeightBelowTheTopSlabIsRefusedNamingItsKey) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  core::VariationOptions v;
  v.surfaces = {{"work_surface", {0.03, 0.03}}};
  try {
    scene->make_trial_layout({}, v, 1);
    FAIL();
  } catch (const core::VariationError& e) {
    EXPECT_EQ(e.key(), "surfaces.work_surface.height_m");
    EXPECT_NE(std::string(e.what()).find("leaves no room under the top"), std::string::npos)
        << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Models, VariationInEveryScene,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::mujoco
