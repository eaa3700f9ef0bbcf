#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/mujoco/mjcf_compose.h"
#include "taskmatrix/mujoco/scene.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using test::RobotEnv;

class LayoutsInEveryScene : public ::testing::TestWithParam<RobotEnv> {};

// Over 1000 seeds the obstacles never touch the robot at its start, a task object or the
// visitor: checked by MuJoCo's own collision detection, not by the generator's geometry.
TEST_P(LayoutsInEveryScene, ThousandSeedsNeverOverlapRobotObjectsOrVisitor) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  const mjModel* m = worker.model();
  std::set<int> obstacle_geoms;
  for (const ObstacleSlot& s : scene->obstacle_slots())
    obstacle_geoms.insert(s.geoms.begin(), s.geoms.end());
  std::set<int> protected_bodies;
  for (const auto& [name, obj] : scene->environment().objects) {
    if (obj.kind == core::ObjectKind::kSurface) continue;
    for (const std::string& b : obj.bodies)
      protected_bodies.insert(mj_name2id(m, mjOBJ_BODY, b.c_str()));
  }
  protected_bodies.insert(mj_name2id(m, mjOBJ_BODY, scene->environment().visitor.body.c_str()));

  const int count = 10;
  int placed = 0;
  for (std::uint64_t seed = 0; seed < 1000; ++seed) {
    const core::ObstacleLayout layout = core::generate_layout(scene->layout_request(count), seed);
    ASSERT_EQ(static_cast<int>(layout.obstacles.size()), count);
    worker.apply_layout(layout);
    worker.reset_to_start();
    for (int i = 0; i < worker.data()->ncon; ++i) {
      const mjContact& c = worker.data()->contact[i];
      const bool o1 = obstacle_geoms.count(c.geom1), o2 = obstacle_geoms.count(c.geom2);
      if (!o1 && !o2) continue;
      const int other = o1 ? c.geom2 : c.geom1;
      ASSERT_FALSE(scene->is_robot_geom(other))
          << "seed " << seed << ": obstacle touches the robot";
      ASSERT_FALSE(protected_bodies.count(m->geom_bodyid[other]))
          << "seed " << seed << ": obstacle touches "
          << mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[other]);
    }
    // MuJoCo does not report contacts between static bodies (furniture, debris, obstacles):
    // check those footprints geometrically, against the environment file's rectangles and
    // the protected bodies' geoms as compiled.
    for (const core::PlacedObstacle& o : layout.obstacles) {
      const double x = o.position.x(), y = o.position.y();
      for (const core::Rect2& r : scene->environment().keep_out) {
        ASSERT_GE(core::distance_to_rect(x, y, r), o.footprint_radius) << "seed " << seed;
      }
      for (const core::Rect2& r : scene->environment().obstacle_regions[o.region].keep_out) {
        ASSERT_GE(core::distance_to_rect(x, y, r), o.footprint_radius) << "seed " << seed;
      }
      for (int g = 0; g < m->ngeom; ++g) {
        int b = m->geom_bodyid[g];
        while (b > 0 && !protected_bodies.count(b)) b = m->body_parentid[b];
        if (b <= 0) continue;
        const double* gp = worker.data()->geom_xpos + 3 * g;
        ASSERT_GE(std::hypot(x - gp[0], y - gp[1]), o.footprint_radius + m->geom_rbound[g] - 1e-9)
            << "seed " << seed << ": obstacle over "
            << mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
      }
    }
    placed += count;
  }
  EXPECT_EQ(placed, 10000);
}

TEST_P(LayoutsInEveryScene, WritesOnlyTheWorkersCopyAndIsRepeatable) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene a(scene), b(scene);
  const int slot_body = scene->obstacle_slots().at(0).body;
  const double shared_z = scene->model()->body_pos[3 * slot_body + 2];
  const core::ObstacleLayout layout = core::generate_layout(scene->layout_request(6), 77);
  a.apply_layout(layout);
  b.apply_layout(core::generate_layout(scene->layout_request(6), 3));
  b.apply_layout(layout);  // re-applying over another layout leaves no trace of it
  a.reset_to_start();
  b.reset_to_start();
  EXPECT_EQ(scene->model()->body_pos[3 * slot_body + 2], shared_z)
      << "the shared model was written";
  for (int g = 0; g < a.model()->ngeom; ++g) {
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(a.data()->geom_xpos[3 * g + k], b.data()->geom_xpos[3 * g + k]);
    ASSERT_EQ(a.model()->geom_contype[g], b.model()->geom_contype[g]);
  }
  // Exactly the six obstacles collide and are visible.
  int enabled = 0;
  for (const ObstacleSlot& s : scene->obstacle_slots()) {
    for (int g : s.geoms)
      enabled += a.model()->geom_contype[g] != 0 && a.model()->geom_group[g] == 0;
  }
  EXPECT_EQ(enabled, 6);
}

TEST_P(LayoutsInEveryScene, ObstaclesReachEveryRegionTheTableTopIncluded) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  const auto& regions = scene->environment().obstacle_regions;
  ASSERT_GE(regions.size(), 2u);
  std::vector<int> per_region(regions.size(), 0);
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    for (const auto& o : core::generate_layout(scene->layout_request(10), seed).obstacles)
      ++per_region[o.region];
  }
  for (size_t r = 0; r < regions.size(); ++r) {
    EXPECT_GE(per_region[r], 5) << "region " << regions[r].name << " never gets obstacles";
  }
}

TEST_P(LayoutsInEveryScene, MoreObstaclesThanSlotsIsAnError) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  EXPECT_THROW(scene->layout_request(scene->environment().obstacle_slots + 1), core::InputError);
  WorkerScene worker(scene);
  core::ObstacleLayout layout;
  layout.obstacles.resize(scene->obstacle_slots().size() + 1);
  EXPECT_THROW(worker.apply_layout(layout), core::LayoutError);
}

INSTANTIATE_TEST_SUITE_P(Models, LayoutsInEveryScene,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::mujoco
