#include "taskmatrix/core/obstacle_layout.h"

#include <gtest/gtest.h>

#include <cmath>

namespace taskmatrix::core {
namespace {

LayoutRequest crowded_room(int count) {
  LayoutRequest req;
  req.count = count;
  req.regions = {{"floor", -2.0, 3.0, -2.0, 2.0, 0.0, {}},
                 {"table", 0.3, 0.9, -0.6, 0.6, 0.65, {}}};
  req.protected_disks = {{0.0, 0.0, 0.6}};
  req.protected_rects = {{0.38, 0.46, -0.16, -0.08}, {1.0, 1.4, 1.0, 1.9}};
  return req;
}

TEST(ObstacleLayout, SameSeedGivesTheSameLayoutBitForBit) {
  const LayoutRequest req = crowded_room(12);
  const ObstacleLayout a = generate_layout(req, 42);
  const ObstacleLayout b = generate_layout(req, 42);
  ASSERT_EQ(a.obstacles.size(), 12u);
  ASSERT_EQ(b.obstacles.size(), 12u);
  for (size_t i = 0; i < a.obstacles.size(); ++i) {
    EXPECT_EQ(a.obstacles[i].shape, b.obstacles[i].shape);
    EXPECT_EQ(a.obstacles[i].position, b.obstacles[i].position);
    EXPECT_EQ(a.obstacles[i].size, b.obstacles[i].size);
    EXPECT_EQ(a.obstacles[i].yaw, b.obstacles[i].yaw);
  }
}

// Pinned values: the generator must give these on every platform and build. A change here
// changes every stored benchmark layout; if it is deliberate, say so in the release notes.
TEST(ObstacleLayout, GoldenLayoutForSeedSeven) {
  LayoutRequest req;
  req.count = 3;
  req.regions = {{"floor", -2.0, 3.0, -2.0, 2.0, 0.0, {}},
                 {"table", 0.3, 0.9, -0.6, 0.6, 0.65, {}}};
  req.protected_disks = {{0.0, 0.0, 0.6}};
  const ObstacleLayout l = generate_layout(req, 7);
  ASSERT_EQ(l.obstacles.size(), 3u);
  EXPECT_EQ(l.obstacles[0].shape, ObstacleShape::kSphere);
  EXPECT_DOUBLE_EQ(l.obstacles[0].position.x(), 2.129766192744865);
  EXPECT_DOUBLE_EQ(l.obstacles[0].position.y(), 1.5632572065226138);
  EXPECT_DOUBLE_EQ(l.obstacles[0].size.x(), 0.049393142482761443);
  EXPECT_EQ(l.obstacles[2].shape, ObstacleShape::kBox);
  EXPECT_DOUBLE_EQ(l.obstacles[2].position.x(), 0.5003135336137996);
  EXPECT_DOUBLE_EQ(l.obstacles[2].position.y(), -1.8360956582221453);
  EXPECT_DOUBLE_EQ(l.obstacles[2].position.z(), 0.2167411830428817);
  EXPECT_DOUBLE_EQ(l.obstacles[2].yaw, 0.89302912057857409);
}

TEST(ObstacleLayout, RegionKeepOutProtectsOnlyItsRegion) {
  LayoutRequest req;
  req.count = 30;
  // Two regions with the same footprint: keep-out of the left half in the first only.
  req.regions = {{"floor", 0.0, 2.0, 0.0, 2.0, 0.0, {{0.0, 1.0, 0.0, 2.0}}},
                 {"shelf", 0.0, 2.0, 0.0, 2.0, 1.0, {}}};
  req.footprint_min_m = 0.03;
  req.footprint_max_m = 0.05;
  int shelf_left = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    for (const PlacedObstacle& o : generate_layout(req, seed).obstacles) {
      if (o.region == 0) {
        ASSERT_GE(o.position.x() - o.footprint_radius, 1.0 + req.clearance_m - 1e-12)
            << "seed " << seed;
      } else {
        shelf_left += o.position.x() < 1.0;
      }
    }
  }
  EXPECT_GT(shelf_left, 100) << "the floor's keep-out must not protect the shelf";
}

TEST(ObstacleLayout, DifferentSeedsGiveDifferentLayouts) {
  const LayoutRequest req = crowded_room(5);
  EXPECT_NE(generate_layout(req, 1).obstacles[0].position,
            generate_layout(req, 2).obstacles[0].position);
}

TEST(ObstacleLayout, OverAThousandSeedsNothingProtectedIsEverOverlapped) {
  const LayoutRequest req = crowded_room(14);
  for (std::uint64_t seed = 0; seed < 1000; ++seed) {
    const ObstacleLayout layout = generate_layout(req, seed);
    ASSERT_EQ(layout.obstacles.size(), 14u) << "seed " << seed;
    for (size_t i = 0; i < layout.obstacles.size(); ++i) {
      const PlacedObstacle& o = layout.obstacles[i];
      const ObstacleRegion& r = req.regions[o.region];
      const double x = o.position.x(), y = o.position.y(), fr = o.footprint_radius;
      ASSERT_GE(x - fr, r.x_min - 1e-12) << "seed " << seed;
      ASSERT_LE(x + fr, r.x_max + 1e-12) << "seed " << seed;
      ASSERT_GE(y - fr, r.y_min - 1e-12) << "seed " << seed;
      ASSERT_LE(y + fr, r.y_max + 1e-12) << "seed " << seed;
      ASSERT_GE(fr, req.footprint_min_m - 1e-12);
      for (const Disk2& d : req.protected_disks) {
        ASSERT_GE(std::hypot(x - d.x, y - d.y), d.radius + fr) << "seed " << seed;
      }
      for (const Rect2& rect : req.protected_rects) {
        ASSERT_GE(distance_to_rect(x, y, rect), fr) << "seed " << seed;
      }
      for (size_t j = 0; j < i; ++j) {
        const PlacedObstacle& p = layout.obstacles[j];
        ASSERT_GE(std::hypot(x - p.position.x(), y - p.position.y()), fr + p.footprint_radius)
            << "seed " << seed << " obstacles " << i << " and " << j;
      }
      // Resting on its region's surface.
      const double half_height = o.shape == ObstacleShape::kSphere ? o.size.x() : o.size.z();
      const double expected_bottom = r.z;
      const double bottom = o.shape == ObstacleShape::kCylinder ? o.position.z() - o.size.y()
                                                                : o.position.z() - half_height;
      ASSERT_NEAR(bottom, expected_bottom, 1e-12);
    }
  }
}

TEST(ObstacleLayout, SaysSoWhenTheRequestedCountCannotBePlaced) {
  LayoutRequest req;
  req.count = 50;
  req.regions = {{"tiny", 0.0, 0.6, 0.0, 0.6, 0.0, {}}};
  req.max_attempts_per_obstacle = 200;
  try {
    generate_layout(req, 3);
    FAIL() << "50 obstacles do not fit in 0.36 m^2 and the generator must say so";
  } catch (const LayoutError& e) {
    EXPECT_NE(std::string(e.what()).find("of 50 obstacles"), std::string::npos) << e.what();
  }
}

TEST(ObstacleLayout, RejectsInconsistentRequests) {
  LayoutRequest req = crowded_room(3);
  req.footprint_min_m = 0.2;
  req.footprint_max_m = 0.1;
  EXPECT_THROW(generate_layout(req, 1), LayoutError);
  req = crowded_room(3);
  req.regions.clear();
  EXPECT_THROW(generate_layout(req, 1), LayoutError);
  req = crowded_room(3);
  req.regions[0].x_max = std::nan("");
  EXPECT_THROW(generate_layout(req, 1), LayoutError);
}

TEST(ObstacleLayout, ZeroObstaclesIsAnEmptyLayout) {
  EXPECT_TRUE(generate_layout(crowded_room(0), 9).obstacles.empty());
}

}  // namespace
}  // namespace taskmatrix::core
