// Task variations (core/task_variation.h) and targeted obstacle groups: the same seed gives the
// same values, placed objects never overlap anything, every key draws from its own stream, and
// bad values name the key at fault.
#include "taskmatrix/core/task_variation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace taskmatrix::core {
namespace {

// A table with two objects and a flake on it, a counter beside it.
WorldGeometry room() {
  WorldGeometry w;
  SurfaceGeometry table;
  table.name = "work_surface";
  table.top = {0.3, 1.0, -0.6, 0.6};
  table.height = 0.65;
  table.area = {"table_top", 0.36, 0.94, -0.54, 0.54, 0.65, {}};
  SurfaceGeometry counter;
  counter.name = "side_surface";
  counter.top = {-0.35, 0.25, 0.55, 1.0};
  counter.height = 0.68;
  counter.area = {"side_surface", -0.32, 0.22, 0.58, 0.97, 0.68, {}};
  w.surfaces = {table, counter};
  auto object = [](const char* name, ObjectKind kind, double x, double y, double r) {
    ObjectGeometry o;
    o.name = name;
    o.kind = kind;
    o.x = x;
    o.y = y;
    o.z = 0.70;
    o.radius = r;
    o.below = 0.05;
    o.above = 0.05;
    o.rests_on = "work_surface";
    o.footprint = {x - r, x + r, y - r, y + r};
    return o;
  };
  w.objects = {object("cup", ObjectKind::kGraspable, 0.42, -0.12, 0.054),
               object("box", ObjectKind::kGraspable, 0.42, 0.15, 0.036),
               object("debris_0", ObjectKind::kDebris, 0.6, -0.3, 0.028)};
  return w;
}

VariationOptions everything() {
  VariationOptions v;
  v.objects = {{"cup", "work_surface", {0, 1, 0, 1}, ValueRange{-3.14, 3.14}},
               {"box", "work_surface", {0, 0.5, 0, 1}, std::nullopt}};
  v.surfaces = {{"work_surface", {0.55, 0.80}}};
  v.robot_start = RobotStartOptions{{-0.05, 0.05}, {-0.1, 0.1}, {-0.2, 0.2}};
  return v;
}

void expect_same(const TaskVariation& a, const TaskVariation& b) {
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].x, b.objects[i].x);
    EXPECT_EQ(a.objects[i].y, b.objects[i].y);
    EXPECT_EQ(a.objects[i].z, b.objects[i].z);
    EXPECT_EQ(a.objects[i].yaw_rad, b.objects[i].yaw_rad);
  }
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (size_t i = 0; i < a.surfaces.size(); ++i)
    EXPECT_EQ(a.surfaces[i].height_m, b.surfaces[i].height_m);
  ASSERT_EQ(a.robot_start.has_value(), b.robot_start.has_value());
  if (a.robot_start) {
    EXPECT_EQ(a.robot_start->x, b.robot_start->x);
    EXPECT_EQ(a.robot_start->yaw, b.robot_start->yaw);
  }
}

TEST(TaskVariation, TheSameSeedGivesTheSameValuesAndAnotherSeedOthers) {
  const WorldGeometry w = room();
  const TaskVariation a = draw_variation(everything(), w, 11);
  expect_same(a, draw_variation(everything(), w, 11));
  const TaskVariation c = draw_variation(everything(), w, 12);
  EXPECT_NE(a.objects[0].x, c.objects[0].x);
  EXPECT_NE(a.surfaces[0].height_m, c.surfaces[0].height_m);
  EXPECT_TRUE(draw_variation(VariationOptions{}, w, 11).empty());
}

TEST(TaskVariation, EachKeyDrawsFromItsOwnStream) {
  const WorldGeometry w = room();
  VariationOptions only_objects = everything();
  only_objects.surfaces.clear();
  only_objects.robot_start.reset();
  VariationOptions only_start;
  only_start.robot_start = everything().robot_start;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const TaskVariation all = draw_variation(everything(), w, seed);
    const TaskVariation objects = draw_variation(only_objects, w, seed);
    // Objects land at the same places whatever else varies (only their height follows).
    for (size_t i = 0; i < all.objects.size(); ++i) {
      EXPECT_EQ(all.objects[i].x, objects.objects[i].x);
      EXPECT_EQ(all.objects[i].y, objects.objects[i].y);
      EXPECT_NEAR(all.objects[i].z - objects.objects[i].z, all.surfaces[0].shift_m, 1e-12);
    }
    EXPECT_EQ(all.robot_start->x, draw_variation(only_start, w, seed).robot_start->x);
  }
}

TEST(TaskVariation, PlacedObjectsNeverOverlapEachOtherOrWhatStaysAndStayInTheirArea) {
  const WorldGeometry w = room();
  const VariationOptions v = everything();
  for (std::uint64_t seed = 0; seed < 2000; ++seed) {
    const TaskVariation t = draw_variation(v, w, seed);
    ASSERT_EQ(t.objects.size(), 2u);
    const double h = t.surfaces[0].height_m;
    ASSERT_GE(h, 0.55);
    ASSERT_LE(h, 0.80);
    const ObjectDraw &cup = t.objects[0], &box = t.objects[1];
    ASSERT_GE(std::hypot(cup.x - box.x, cup.y - box.y), 0.054 + 0.036 + v.clearance_m)
        << "seed " << seed;
    for (const ObjectDraw& o : t.objects) {
      const double r = o.object == "cup" ? 0.054 : 0.036;
      ASSERT_GE(std::hypot(o.x - 0.6, o.y + 0.3), r + 0.028 + v.clearance_m) << "the flake";
      ASSERT_GE(o.x - r, 0.36 - 1e-12);
      ASSERT_LE(o.y + r, 0.54 + 1e-12);
      ASSERT_NEAR(o.z, h + 0.05 + kRestGapM, 1e-12) << "just above the surface at its height";
    }
    // The box's area is the near half of the table's.
    ASSERT_LE(box.x + 0.036, 0.36 + 0.5 * 0.58 + 1e-12);
    ASSERT_GE(std::abs(cup.yaw_rad), 0.0);
    ASSERT_EQ(box.yaw_rad, 0.0) << "no yaw range: the model file's orientation";
  }
}

TEST(TaskVariation, BadValuesNameTheirKey) {
  const WorldGeometry w = room();
  auto key_of = [&](const VariationOptions& v) -> std::string {
    try {
      draw_variation(v, w, 1);
    } catch (const VariationError& e) {
      return e.key() + ": " + e.what();
    }
    return "";
  };
  VariationOptions v = everything();
  v.objects[0].object = "cupp";
  EXPECT_EQ(key_of(v).rfind("objects.cupp: no graspable object or tool 'cupp'", 0), 0u)
      << key_of(v);
  v = everything();
  v.objects[1].surface = "floor";
  EXPECT_EQ(key_of(v).rfind("objects.box.on: no surface 'floor'", 0), 0u) << key_of(v);
  v = everything();
  v.surfaces[0].height_m = {0.9, 0.5};
  EXPECT_EQ(key_of(v).rfind("surfaces.work_surface.height_m:", 0), 0u) << key_of(v);
  v = everything();
  v.robot_start->yaw_rad = {0.3, -0.3};
  EXPECT_EQ(key_of(v).rfind("robot_start.yaw:", 0), 0u) << key_of(v);
  v = everything();
  v.objects.push_back(v.objects[0]);
  EXPECT_EQ(key_of(v).rfind("objects.cup: is listed twice", 0), 0u) << key_of(v);
  v = everything();
  v.objects[0].area = {0.0, 0.05, 0.0, 0.05};  // 3 cm x 5 cm: the cup cannot fit
  EXPECT_EQ(key_of(v).rfind("objects.cup: 'cup'", 0), 0u) << key_of(v);
}

TEST(TaskVariation, ObjectsAndObstaclesMoveWithTheSurface) {
  const WorldGeometry w = room();
  TaskVariation t;
  t.surfaces = {{"work_surface", 0.75, 0.10}};
  const WorldGeometry v = varied(w, t);
  EXPECT_DOUBLE_EQ(v.surface("work_surface")->area.z, 0.75);
  EXPECT_DOUBLE_EQ(v.object("cup")->z, 0.80);
  EXPECT_DOUBLE_EQ(v.object("cup")->footprint.z_top, 0.85);
  EXPECT_DOUBLE_EQ(v.surface("side_surface")->height, 0.68);
}

// A start at which the robot would touch the world (the check says so) is drawn again from the
// start's own stream: surfaces and objects stay as drawn, the obstacles keep clear of the start
// finally drawn, the record says which draw it is, and the same seed redraws alike. A start
// clear at once is the first draw, as without a check. No start in kStartDraws draws is
// `robot_start`'s error, with the last reason.
TEST(TaskVariation, AStartTheRobotWouldTouchTheWorldFromIsDrawnAgain) {
  const WorldGeometry w = room();
  const VariationOptions v = everything();
  LayoutRequest seen;
  auto request = [&](const TaskVariation& t) {
    const WorldGeometry world = varied(w, t);
    LayoutRequest req;
    req.protected_disks = {{world.start.x, world.start.y, 0.6}};
    seen = req;
    return req;
  };
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    const TrialLayout plain = draw_world(v, w, request, seed);
    ASSERT_EQ(plain.variation.start_draw, 0);
    // Clear at once: the first draw.
    const TrialLayout clear =
        draw_world(v, w, request, seed, [](const TaskVariation&) { return std::nullopt; });
    expect_same(plain.variation, clear.variation);
    EXPECT_EQ(clear.variation.start_draw, 0);
    // Clear only at starts forward of the environment's: drawn again until one is.
    int checks = 0;
    const StartCheck forward = [&](const TaskVariation& t) -> std::optional<std::string> {
      ++checks;
      if (t.robot_start->x > 0.02) return std::nullopt;
      return std::string("l_finger touches table_top (depth 1.8 mm)");
    };
    const TrialLayout redrawn = draw_world(v, w, request, seed, forward);
    const TaskVariation& r = redrawn.variation;
    ASSERT_GT(r.robot_start->x, 0.02) << "seed " << seed;
    EXPECT_EQ(r.start_draw, checks - 1);
    EXPECT_EQ(r.start_draw == 0, plain.variation.robot_start->x > 0.02);
    ASSERT_EQ(r.objects.size(), plain.variation.objects.size());
    for (size_t i = 0; i < r.objects.size(); ++i) {
      EXPECT_EQ(r.objects[i].x, plain.variation.objects[i].x);
      EXPECT_EQ(r.objects[i].y, plain.variation.objects[i].y);
    }
    EXPECT_EQ(r.surfaces[0].height_m, plain.variation.surfaces[0].height_m);
    EXPECT_EQ(seen.protected_disks[0].x, r.robot_start->x);
    EXPECT_EQ(seen.protected_disks[0].y, r.robot_start->y);
    EXPECT_GE(r.robot_start->x, -0.05);
    EXPECT_LE(r.robot_start->x, 0.05);
    EXPECT_LE(std::abs(r.robot_start->y), 0.1);
    expect_same(r, draw_world(v, w, request, seed, forward).variation);
  }
  try {
    draw_world(v, w, request, 7, [](const TaskVariation&) {
      return std::optional<std::string>("l_finger touches table_top (depth 1.8 mm)");
    });
    FAIL() << "no start is ever clear";
  } catch (const VariationError& e) {
    EXPECT_EQ(e.key(), "robot_start");
    EXPECT_NE(std::string(e.what()).find(std::to_string(kStartDraws) + " draws"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("l_finger touches table_top"), std::string::npos);
  }
  // Without a varied start there is nothing to draw again: the check is not asked.
  VariationOptions fixed = v;
  fixed.robot_start.reset();
  int asked = 0;
  draw_world(fixed, w, request, 3, [&](const TaskVariation&) {
    ++asked;
    return std::optional<std::string>("anything");
  });
  EXPECT_EQ(asked, 0);
}

TEST(TargetedObstacles, NearObstaclesSurroundTheDrawnObjectAndNeverTouchIt) {
  const WorldGeometry w = room();
  const VariationOptions v = everything();
  TargetedObstacles near = targeted_defaults(TargetedObstacles::Kind::kNear);
  near.object = "cup";
  near.count = 6;
  near.radius_m = 0.3;
  TargetedObstacles over = targeted_defaults(TargetedObstacles::Kind::kOverhead);
  over.object = "cup";
  over.count = 2;
  int redrawn = 0;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    auto request = [&](const TaskVariation& t) {
      const WorldGeometry world = varied(w, t);
      LayoutRequest req;
      req.protected_disks = {{world.start.x, world.start.y, 0.6}};
      for (const ObjectGeometry& o : world.objects) req.protected_rects.push_back(o.footprint);
      req.groups = targeted_groups({near, over}, world, {}, 0.25, 0.2);
      return req;
    };
    const TrialLayout trial = draw_world(v, w, request, seed);
    const TrialLayout again = draw_world(v, w, request, seed);
    ASSERT_EQ(trial.draw, again.draw);
    expect_same(trial.variation, again.variation);
    redrawn += trial.draw > 0;
    const WorldGeometry world = varied(w, trial.variation);
    const ObstacleLayout& layout = trial.obstacles;
    ASSERT_EQ(layout.obstacles.size(), 8u);
    const ObjectGeometry& cup = *world.object("cup");
    const double h = world.surface("work_surface")->height;
    for (const PlacedObstacle& o : layout.obstacles) {
      const double x = o.position.x(), y = o.position.y();
      ASSERT_LE(std::hypot(x - cup.x, y - cup.y), o.group == 0 ? 0.3 : 0.3 + 1e-12);
      for (const ObjectGeometry& k : world.objects) {
        const bool above = o.hanging && o.position.z() - o.half_height() >= k.footprint.z_top;
        ASSERT_TRUE(above || distance_to_rect(x, y, k.footprint) >= o.footprint_radius)
            << "seed " << seed << ": an obstacle on " << k.name;
      }
      if (o.hanging) {
        ASSERT_GE(o.position.z() - o.half_height(), h + over.lift_min_m - 1e-12);
        ASSERT_LE(o.position.z() - o.half_height(), h + over.lift_max_m + 1e-12);
      } else {
        ASSERT_NEAR(o.position.z() - o.half_height(), h, 1e-12) << "rests on the moved table";
      }
    }
    ASSERT_EQ(layout.groups.size(), 2u);
    EXPECT_EQ(layout.groups[0], "obstacles near cup");
  }
  // Six obstacles within 30 cm of a cup that may stand in a corner: some seeds need a redraw.
  EXPECT_GT(redrawn, 0);
  EXPECT_LT(redrawn, 60);
}

TEST(TargetedObstacles, UnknownNamesAndImpossibleCountsNameTheirKey) {
  const WorldGeometry w = room();
  TargetedObstacles near = targeted_defaults(TargetedObstacles::Kind::kNear);
  near.object = "mug";
  near.count = 2;
  try {
    targeted_groups({near}, w, {}, 0.25, 0.2);
    FAIL();
  } catch (const VariationError& e) {
    EXPECT_EQ(e.key(), "obstacles.near.object");
  }
  near.object = "cup";
  near.count = 60;
  near.radius_m = 0.1;
  LayoutRequest req;
  req.groups = targeted_groups({near}, w, {}, 0.25, 0.2);
  try {
    generate_layout(req, 1);
    FAIL();
  } catch (const LayoutError& e) {
    EXPECT_EQ(e.key(), "obstacles.near");
    EXPECT_NE(std::string(e.what()).find("of 60 obstacles near cup"), std::string::npos)
        << e.what();
  }
}

TEST(TargetedObstacles, PathAndFloorObstaclesLieInTheirCorridors) {
  const WorldGeometry w = room();
  TargetedObstacles path = targeted_defaults(TargetedObstacles::Kind::kPath);
  path.object = "cup";
  path.surface = "side_surface";
  path.count = 3;
  TargetedObstacles floor = targeted_defaults(TargetedObstacles::Kind::kFloor);
  floor.surface = "work_surface";
  floor.count = 2;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    LayoutRequest req;
    req.protected_disks = {{0, 0, 0.6}};
    req.groups = targeted_groups({path, floor}, w, {}, 0.25, 0.2);
    const ObstacleLayout layout = generate_layout(req, seed);
    ASSERT_EQ(layout.obstacles.size(), 5u);
    for (const PlacedObstacle& o : layout.obstacles) {
      const Corridor2& c = *req.groups[static_cast<size_t>(o.group)].along;
      ASSERT_LE(distance_to_segment(o.position.x(), o.position.y(), c), c.half_width + 1e-12);
      if (o.group == 1) {
        ASSERT_NEAR(o.position.z() - o.half_height(), 0.0, 1e-12);
        ASSERT_GE(std::hypot(o.position.x(), o.position.y()), 0.2 + o.footprint_radius)
            << "clear of the robot's feet";
        ASSERT_GE(distance_to_rect(o.position.x(), o.position.y(), w.surfaces[0].top),
                  o.footprint_radius)
            << "not under the table";
      }
    }
  }
}

}  // namespace
}  // namespace taskmatrix::core
