// Conditions in true and false cases on the fake skillset (tests/support/fake_skillset.h), no
// simulator: on hand-made boxes and the fake's kitchen, placements generated from them, the
// text form and its errors, and the reference (docs/conditions.md) against the parser. What
// only the built-in scenes show (the cup on the work surface, in view at rest, for each robot)
// is in tests/mujoco/scene_conditions_test.cc.
#include "taskmatrix/core/conditions.h"

#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "tests/support/fake_skillset.h"

namespace taskmatrix::core {
namespace {

PerceivedObject box_object(const std::string& id, Eigen::Vector3d lo, Eigen::Vector3d hi) {
  PerceivedObject o;
  o.id = id;
  o.type = "graspable";
  o.box = Eigen::AlignedBox3d(lo, hi);
  o.pose.position = o.box.center();
  return o;
}

// The fake's kitchen with crumbs on the floor, out of the arms' way.
std::vector<test::FakeBox> kitchen_with_debris() {
  std::vector<test::FakeBox> world = test::fake_kitchen();
  world.push_back(
      {"crumbs", "debris",
       Eigen::AlignedBox3d(Eigen::Vector3d(1.5, -0.5, 0), Eigen::Vector3d(1.55, -0.45, 0.02))});
  return world;
}

class ConditionsTest : public ::testing::Test {
 protected:
  void SetUp() override { skills_.perceive(percepts_); }
  World world() { return World{skills_, percepts_}; }
  // A palm pose at `position`, facing along the base's +x.
  static Pose palm_at(const Eigen::Vector3d& position) {
    Pose p;
    p.position = position;
    return p;
  }
  test::FakeSkillset skills_{kitchen_with_debris()};
  PerceptualModel percepts_;
};

TEST_F(ConditionsTest, NearAndAboveOnHandMadeBoxes) {
  percepts_.observe(box_object("a", {0, 0, 1.0}, {0.1, 0.1, 1.1}));
  percepts_.observe(box_object("b", {0.15, 0, 1.0}, {0.3, 0.1, 1.1}));     // 5 cm to the side
  percepts_.observe(box_object("c", {-0.5, -0.5, 0.5}, {0.5, 0.5, 1.0}));  // a table under a
  EXPECT_TRUE(near("a", "b")->holds(world()));
  EXPECT_FALSE(near("a", "b", 0.04)->holds(world()));
  EXPECT_TRUE(above("a", "c")->holds(world()));
  EXPECT_FALSE(above("c", "a")->holds(world()));
  EXPECT_FALSE(above("a", "b")->holds(world()));     // projections do not intersect
  EXPECT_FALSE(near("a", "ghost")->holds(world()));  // unknown objects make it false
  EXPECT_TRUE(negate(near("a", "ghost"))->holds(world()));
  EXPECT_TRUE(any_of({near("a", "ghost"), above("a", "c")})->holds(world()));
  EXPECT_FALSE(all_of({near("a", "ghost"), above("a", "c")})->holds(world()));
  EXPECT_EQ(all_of({near("a", "b"), negate(above("a", "c"))})->describe(),
            "all_of(near(a, b, 0.1), not(above(a, c)))");
  // Why a condition is false: the clause that fails and what was measured.
  EXPECT_EQ(near("a", "b", 0.04)->explain(world()), "near(a, b, 0.04): a is 5.0 cm from b");
  EXPECT_EQ(above("a", "b")->explain(world()), "above(a, b): a is not over b");
  EXPECT_EQ(above("c", "a")->explain(world()), "above(c, a): c's bottom is 60.0 cm below a's top");
  EXPECT_EQ(near("a", "ghost")->explain(world()),
            "near(a, ghost, 0.1): ghost unknown to the perceptual model");
  EXPECT_EQ(all_of({above("a", "c"), near("a", "b", 0.04)})->explain(world()),
            "near(a, b, 0.04): a is 5.0 cm from b");
  EXPECT_EQ(any_of({above("a", "b"), negate(above("a", "c"))})->explain(world()),
            "none of 2 holds: above(a, b): a is not over b; not(above(a, c)): above(a, c) holds");
  EXPECT_EQ(above("a", "c")->explain(world()), "above(a, c) holds");
}

TEST_F(ConditionsTest, TheCupStandsOnTheWorkSurfaceNotTheShelf) {
  EXPECT_TRUE(above("cup", "work_surface")->holds(world()));
  EXPECT_TRUE(near("cup", "work_surface")->holds(world()));
  EXPECT_FALSE(above("cup", "shelf")->holds(world()));
  EXPECT_FALSE(above("work_surface", "cup")->holds(world()));
  EXPECT_TRUE(
      parse_condition("all_of(above(cup, work_surface), not(grasping(cup)))")->holds(world()));
}

TEST_F(ConditionsTest, PlacementsDrawnFromAboveAndNearSatisfyBoth) {
  const ConditionPtr on_table = all_of({above("cup", "work_surface"), near("cup", "work_surface")});
  std::mt19937_64 rng(4);
  const std::vector<Eigen::AlignedBox3d> boxes =
      sample_placements(*on_table, world(), "cup", rng, 20);
  ASSERT_EQ(boxes.size(), 20u);
  const Eigen::AlignedBox3d table = percepts_.find("work_surface")->box;
  const Eigen::Vector3d cup_size = percepts_.find("cup")->box.sizes();
  for (const Eigen::AlignedBox3d& b : boxes) {
    const Hypothesis h{"cup", b};
    EXPECT_TRUE(above("cup", "work_surface")->holds(world(), &h));
    EXPECT_TRUE(near("cup", "work_surface")->holds(world(), &h));
    EXPECT_NEAR(b.min().z(), table.max().z(), 1e-9);  // resting on the top
    EXPECT_LT((b.sizes() - cup_size).norm(), 1e-9);   // same size
  }
  // The conjunction with a condition that cannot hold yields nothing.
  const ConditionPtr impossible = all_of({above("cup", "work_surface"), near("cup", "ghost")});
  EXPECT_TRUE(sample_placements(*impossible, world(), "cup", rng, 5, 100).empty());
}

// A table 0.7 x 1.2 m turned 20 degrees about the vertical, its top at 0.65 m: its
// world-aligned box reaches 0.53 m and 0.68 m from its centre, its corners lie beside the table.
PerceivedObject turned_table(const std::string& id, const Eigen::Vector2d& centre) {
  PerceivedObject t;
  t.id = id;
  t.type = "surface";
  t.pose.position = Eigen::Vector3d(centre.x(), centre.y(), 0.65);
  t.pose.orientation = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ());
  t.top = Eigen::AlignedBox2d(Eigen::Vector2d(-0.35, -0.6), Eigen::Vector2d(0.35, 0.6));
  const SurfaceTop top = surface_top(t.box, t.pose, t.top);
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d p =
        top.world({corner & 1 ? top.hi.x() : top.lo.x(), corner & 2 ? top.hi.y() : top.lo.y()});
    t.box.extend(Eigen::Vector3d(p.x(), p.y(), 0.61));
    t.box.extend(Eigen::Vector3d(p.x(), p.y(), 0.65));
  }
  return t;
}

TEST(SurfaceTopOfATurnedTable, IsTheTurnedRectangleNotItsWorldAlignedBox) {
  const PerceivedObject table = turned_table("table", {3, 0});
  const SurfaceTop top = surface_top(table);
  ASSERT_TRUE(top.turned());
  EXPECT_NEAR(top.height, 0.65, 1e-12);
  EXPECT_NEAR(top.signed_distance({3, 0}), -0.35, 1e-9);  // the centre, 35 cm from the long edge
  // A corner of the world-aligned box lies more than 10 cm beside the table; the table's own
  // corner on its edge.
  const Eigen::Vector2d box_corner = table.box.max().head<2>();
  EXPECT_GT(top.signed_distance(box_corner), 0.1);
  EXPECT_NEAR(top.signed_distance(top.world(top.hi)), 0, 1e-9);
  EXPECT_NEAR((top.nearest(box_corner) - box_corner).norm(), top.signed_distance(box_corner), 1e-9);
  // A 6 cm footprint at the box's corner is not over the table; one at its centre is.
  const Eigen::Vector2d cup(0.03, 0.03);
  EXPECT_FALSE(top.overlaps(box_corner - 2 * cup, box_corner));
  EXPECT_TRUE(top.overlaps(Eigen::Vector2d(3, 0) - cup, Eigen::Vector2d(3, 0) + cup));
  // The largest world-aligned rectangle inside it lies inside it, and is no sliver.
  const Eigen::AlignedBox2d inside = top.inscribed();
  for (int corner = 0; corner < 4; ++corner) {
    EXPECT_LE(
        top.signed_distance(inside.corner(static_cast<Eigen::AlignedBox2d::CornerType>(corner))),
        1e-9);
  }
  EXPECT_GT(inside.volume(), 0.5 * 0.7 * 1.2 * 0.5);
}

TEST(SurfaceTopOfATableNotTurned, IsItsBoxExactly) {
  PerceivedObject desk = box_object("desk", {0.3, -0.6, 0.61}, {1.0, 0.6, 0.65});
  desk.type = "surface";
  desk.top = Eigen::AlignedBox2d(Eigen::Vector2d(-0.35, -0.6), Eigen::Vector2d(0.35, 0.6));
  const SurfaceTop top = surface_top(desk);
  EXPECT_FALSE(top.turned());
  EXPECT_EQ(top.lo, desk.box.min().head<2>());
  EXPECT_EQ(top.hi, desk.box.max().head<2>());
  EXPECT_EQ(top.height, desk.box.max().z());
  EXPECT_EQ(top.inscribed().min(), top.lo);
  EXPECT_EQ(top.local(Eigen::Vector2d(0.1, 0.2)), Eigen::Vector2d(0.1, 0.2));
}

// Placements on a table turned in its room: drawn on the table, not in the corners of its
// world-aligned box, where a cup set down falls to the floor; and above() does not hold for a
// cup standing there.
TEST_F(ConditionsTest, PlacementsOnATurnedTableLieOnIt) {
  percepts_.observe(turned_table("turned_table", {3, 0}));
  const SurfaceTop top = surface_top(*percepts_.find("turned_table"));
  std::mt19937_64 rng(4);
  const std::vector<Eigen::AlignedBox3d> boxes =
      sample_placements(*above("cup", "turned_table"), world(), "cup", rng, 40);
  ASSERT_EQ(boxes.size(), 40u);
  for (const Eigen::AlignedBox3d& b : boxes) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d c(k & 1 ? b.max().x() : b.min().x(), k & 2 ? b.max().y() : b.min().y());
      EXPECT_LE(top.signed_distance(c), 1e-9) << "a corner of the cup's box off the table";
    }
    EXPECT_NEAR(b.min().z(), 0.65, 1e-9);
  }
  const Eigen::Vector3d cup = percepts_.find("cup")->box.sizes();
  const Eigen::Vector3d corner = percepts_.find("turned_table")->box.max();
  const Hypothesis in_the_corner{
      "cup", Eigen::AlignedBox3d(Eigen::Vector3d(corner.x() - cup.x(), corner.y() - cup.y(), 0.65),
                                 Eigen::Vector3d(corner.x(), corner.y(), 0.65 + cup.z()))};
  EXPECT_FALSE(above("cup", "turned_table")->holds(world(), &in_the_corner));
  const Hypothesis on_it{"cup", boxes.front()};
  EXPECT_TRUE(above("cup", "turned_table")->holds(world(), &on_it));
}

TEST_F(ConditionsTest, TextFormParsesAndEvaluatesLikeTheCalls) {
  const ConditionPtr c = parse_condition(
      "all_of(above(cup, work_surface), near(cup, work_surface, 0.1), "
      "not(grasping(cup)), exists(debris))");
  EXPECT_EQ(c->describe(),
            "all_of(above(cup, work_surface), near(cup, work_surface, 0.1), not(grasping(cup)), "
            "exists(debris))");
  EXPECT_TRUE(c->holds(world()));
  EXPECT_FALSE(parse_condition("exists(teapot)")->holds(world()));
  EXPECT_FALSE(parse_condition("any_of(grasping(cup), graspable(cup))")->holds(world()));
  // The fake's head looks level at rest, over the cup; turned and tilted down, at it. (The
  // built-in robots look at the work surface at rest: tests/mujoco/scene_conditions_test.cc.)
  EXPECT_FALSE(parse_condition("in_view(cup)")->holds(world()));
  EXPECT_EQ(in_view("cup")->explain(world()),
            "in_view(cup): cup is outside the head camera's view");
  skills_.place({"head"}, {0.65, 0.6});
  EXPECT_TRUE(parse_condition("in_view(cup)")->holds(world()));
  EXPECT_EQ(in_view("cup")->explain(world()), "in_view(cup) holds");
  auto error = [](const std::string& text) {
    try {
      parse_condition(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("near(cup)"), "condition 'near(cup)': near takes 2 to 3 arguments, not 1");
  EXPECT_EQ(error("nearby(cup, box)")
                .rfind("condition 'nearby(cup, box)': unknown condition "
                       "'nearby' (known: near, above,",
                       0),
            0u);
  EXPECT_EQ(error("grasping(cup"), "condition 'grasping(cup': expected ')' at position 12");
  EXPECT_EQ(error("near(cup, box, -1)"),
            "condition 'near(cup, box, -1)': near: argument 3 must be a non-negative number, "
            "not '-1'");
  EXPECT_EQ(error("not(cup)"), "condition 'not(cup)': not: argument 1 must be a condition");
}

TEST_F(ConditionsTest, PosturalFollowsTheChains) {
  EXPECT_TRUE(postural("rest")->holds(world()));
  EXPECT_FALSE(postural("fist")->holds(world()));
  EXPECT_FALSE(postural("wave_start")->holds(world()));
  const Posture& fist = skills_.posture("fist");
  skills_.place({"left_hand"}, fist.at("left_hand"));
  EXPECT_FALSE(postural("fist")->holds(world()));  // the right hand is still open
  EXPECT_TRUE(postural("fist", {"left_hand"})->holds(world()));
  EXPECT_FALSE(postural("rest")->holds(world()));
  EXPECT_TRUE(postural("rest", {"right_arm", "head"})->holds(world()));
}

TEST_F(ConditionsTest, GraspingAndGraspableFollowTheHands) {
  EXPECT_FALSE(graspable("cup")->holds(world()));
  EXPECT_FALSE(grasping("cup")->holds(world()));
  // The left palm at the cup's centre (ignoring collisions): graspable by the left hand only.
  IkOptions ik;
  ik.orientation = false;
  ik.collision_free = false;
  const IkResult r =
      skills_.solve_ik({"left_arm"}, "left_palm", palm_at(percepts_.find("cup")->box.center()), ik);
  ASSERT_EQ(r.status, IkStatus::kSolved) << r.reason;
  skills_.command({"left_arm"}, r.solutions.front());
  skills_.advance();
  EXPECT_TRUE(graspable("cup")->holds(world()));
  EXPECT_TRUE(graspable("cup", "left")->holds(world()));
  EXPECT_FALSE(graspable("cup", "right")->holds(world()));
  EXPECT_FALSE(postural("rest")->holds(world()));
  EXPECT_TRUE(postural("rest", {"right_arm", "head"})->holds(world()));

  skills_.attach("cup", "left");
  EXPECT_TRUE(grasping("cup")->holds(world()));
  EXPECT_EQ(skills_.holder_of("cup"), "left");
  EXPECT_FALSE(graspable("cup")->holds(world()));  // already held
  // Lifting the arm's shoulder carries the cup off the table.
  skills_.command({"torso"}, {0.2});
  skills_.advance();
  skills_.perceive(percepts_);
  EXPECT_FALSE(above("cup", "work_surface")->holds(world()) &&
               near("cup", "work_surface", 0.05)->holds(world()));
  EXPECT_NEAR(percepts_.find("cup")->box.center().z(), 1.2, 1e-9);
  skills_.detach("cup");
  EXPECT_FALSE(grasping("cup")->holds(world()));
}

// An object of several shapes is graspable from a palm within 3 cm of a part that sticks out
// beyond the rest (a mug's handle, held on its own), outside the object's box; not from 2 cm
// beside a cup whose base sits under its wall (nothing sticks out).
TEST_F(ConditionsTest, GraspableAtAPartThatSticksOut) {
  const Eigen::Vector3d palm = skills_.frame_pose("left_palm").position;
  auto shape = [](const Eigen::Vector3d& c, const Eigen::Vector3d& half) {
    Shape s;
    s.type = Shape::Type::kBox;
    s.pose.position = c;
    s.size = half;
    return s;
  };
  // Body 8 cm across, 9 cm ahead of the palm; a handle from 4 to 7 cm out of it towards the
  // palm (-x), whose outer face is 2 cm from the palm.
  const Eigen::Vector3d at = palm + Eigen::Vector3d(0.09, 0, 0);
  PerceivedObject mug = box_object("mug", at - Eigen::Vector3d(0.07, 0.04, 0.05),
                                   at + Eigen::Vector3d(0.04, 0.04, 0.05));
  mug.shapes = {shape(at, {0.04, 0.04, 0.05}),
                shape(at - Eigen::Vector3d(0.055, 0, 0), {0.015, 0.006, 0.03})};
  // The body sticks out too, the other way.
  EXPECT_EQ(protruding_shapes(mug), (std::vector<size_t>{0, 1}));
  percepts_.observe(mug);
  EXPECT_TRUE(graspable("mug", "left")->holds(world()));
  EXPECT_EQ(graspable("mug", "left")->explain(world()), "graspable(mug, left) holds");
  EXPECT_FALSE(graspable("mug", "right")->holds(world()));
  // A cup, its wall 2 cm ahead of the palm and a base as wide under it.
  const Eigen::Vector3d cup_at = palm + Eigen::Vector3d(0.06, 0, 0);
  PerceivedObject cup = box_object("cup2", cup_at - Eigen::Vector3d(0.04, 0.04, 0.05),
                                   cup_at + Eigen::Vector3d(0.04, 0.04, 0.05));
  cup.shapes = {shape(cup_at, {0.04, 0.04, 0.05}),
                shape(cup_at - Eigen::Vector3d(0, 0, 0.045), {0.04, 0.04, 0.005})};
  EXPECT_TRUE(protruding_shapes(cup).empty());
  percepts_.observe(cup);
  EXPECT_FALSE(graspable("cup2", "left")->holds(world()));
}

// What the parser says when a condition is called with no arguments: its arity error for a
// known name, the list of known names for an unknown one.
std::string parse_error(const std::string& text) {
  try {
    parse_condition(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// The arity error the parser gives for `name()`, computed from a signature of the reference
// ("near(A, B[, d])": 2 required, 1 optional; "all_of(C...)": 1 or more).
std::string arity_text(const std::string& signature) {
  const size_t open = signature.find('('), close = signature.rfind(')');
  const std::string name = signature.substr(0, open);
  const std::string inside = signature.substr(open + 1, close - open - 1);
  const size_t bracket = inside.find('[');
  const auto count = [](const std::string& part) {
    int n = 0;
    std::stringstream in(part);
    for (std::string item; std::getline(in, item, ',');) {
      if (item.find_first_not_of(" []") != std::string::npos) ++n;
    }
    return n;
  };
  const int required = count(inside.substr(0, bracket));
  const int optional = bracket == std::string::npos ? 0 : count(inside.substr(bracket));
  const bool variadic = inside.find("...") != std::string::npos;
  std::string takes = name + " takes " + std::to_string(required);
  if (variadic) {
    takes += " or more";
  } else if (optional > 0) {
    takes += " to " + std::to_string(required + optional);
  }
  return takes + " argument" + (required == 1 && !variadic && optional == 0 ? "" : "s");
}

TEST(ConditionReference, ListsEveryConditionTheParserAcceptsWithItsArity) {
  // The names the parser accepts, as its unknown-condition error lists them.
  const std::string unknown = parse_error("no_such_condition(cup)");
  const size_t known_at = unknown.find("(known: ");
  ASSERT_NE(known_at, std::string::npos) << unknown;
  std::set<std::string> parsed;
  std::stringstream known(unknown.substr(known_at + 8, unknown.rfind(')') - known_at - 8));
  for (std::string name; std::getline(known, name, ',');) {
    parsed.insert(name.substr(name.find_first_not_of(' ')));
  }
  ASSERT_GE(parsed.size(), 10u) << unknown;

  // The reference's table: every backquoted signature in the first column of its rows.
  std::ifstream file(std::filesystem::path(TASKMATRIX_TEST_ROOT) / "docs" / "conditions.md");
  ASSERT_TRUE(file) << "docs/conditions.md";
  std::set<std::string> documented;
  bool in_table = false;
  for (std::string line; std::getline(file, line);) {
    if (line.rfind("## ", 0) == 0) in_table = line == "## Conditions";
    if (!in_table || line.rfind("| `", 0) != 0) continue;
    const std::string first = line.substr(1, line.find('|', 1) - 1);
    for (size_t at = first.find('`'); at != std::string::npos;
         at = first.find('`', first.find('`', at + 1) + 1)) {
      const std::string signature = first.substr(at + 1, first.find('`', at + 1) - at - 1);
      const std::string name = signature.substr(0, signature.find('('));
      documented.insert(name);
      // The parser knows the name and takes the arguments the signature says.
      const std::string error = parse_error(name + "()");
      EXPECT_NE(error.find(arity_text(signature)), std::string::npos)
          << signature << " in docs/conditions.md; the parser says: " << error;
    }
  }
  EXPECT_EQ(documented, parsed) << "docs/conditions.md lists other conditions than the parser";

  // The defaults the reference gives.
  EXPECT_EQ(parse_condition("near(cup, work_surface)")->describe(), "near(cup, work_surface, 0.1)");
  EXPECT_EQ(parse_condition("graspable(cup)")->describe(), "graspable(cup, any)");
}

}  // namespace
}  // namespace taskmatrix::core
