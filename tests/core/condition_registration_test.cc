// A condition added the way a user adds one: one registration in this file, and the text form
// (scenario success criteria, guards, invariants) knows it. Its own test executable, so the
// condition stays out of the registry the reference test (conditions_test.cc) checks against
// docs/conditions.md.
#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "tests/test_support.h"

namespace taskmatrix::core {
namespace {

// higher(A, B[, d]): A's bottom is at least d (default 0) above B's top.
class Higher final : public Condition {
 public:
  Higher(std::string a, std::string b, double d) : a_(std::move(a)), b_(std::move(b)), d_(d) {}
  bool holds(const World& w, const Hypothesis*) const override {
    const PerceivedObject* a = w.percepts.find(a_);
    const PerceivedObject* b = w.percepts.find(b_);
    return a && b && a->box.min().z() >= b->box.max().z() + d_;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "higher(" << a_ << ", " << b_ << ", " << d_ << ")";
    return s.str();
  }

 private:
  std::string a_, b_;
  double d_;
};

// The one registration.
const ConditionRegistration kHigher{
    {"higher",
     2,
     3,
     {ConditionArgKind::kObject, ConditionArgKind::kObject, ConditionArgKind::kNumber},
     [](const std::vector<ConditionArg>& a) {
       return std::make_shared<Higher>(a[0].name, a[1].name, a.size() == 3 ? a[2].number : 0.0);
     }}};

std::string parse_error(const std::string& text) {
  try {
    parse_condition(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(ConditionRegistration, AUserConditionParsesAndEvaluatesOnARealWorld) {
  mujoco::MujocoSkillset skills(test::scene("tallbot", "kitchen"));
  PerceptualModel percepts;
  mujoco::GroundTruthPerception(skills).update(0, percepts);
  const World world{skills, percepts};
  ASSERT_TRUE(percepts.knows("cup"));

  // Hand-made boxes: a 10 cm cube resting 2 cm above a table top.
  PerceivedObject cube, table;
  cube.id = "cube", table.id = "slab";
  cube.box = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 1.02), Eigen::Vector3d(0.1, 0.1, 1.12));
  table.box = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -0.5, 0.9), Eigen::Vector3d(0.5, 0.5, 1));
  percepts.observe(cube);
  percepts.observe(table);
  EXPECT_TRUE(parse_condition("higher(cube, slab)")->holds(world));
  EXPECT_TRUE(parse_condition("higher(cube, slab, 0.015)")->holds(world));
  EXPECT_FALSE(parse_condition("higher(cube, slab, 0.025)")->holds(world));
  EXPECT_FALSE(parse_condition("higher(slab, cube)")->holds(world));
  EXPECT_FALSE(parse_condition("higher(cube, ghost)")->holds(world));
  // The scene's cup stands on its work surface, not 10 cm above it.
  EXPECT_FALSE(parse_condition("higher(cup, work_surface, 0.1)")->holds(world));
  EXPECT_FALSE(parse_condition("higher(work_surface, cup)")->holds(world));
  EXPECT_EQ(parse_condition("higher(cup, work_surface)")->describe(),
            "higher(cup, work_surface, 0)");

  // It composes with the built-ins, and the default explain() says whether it holds.
  const ConditionPtr composed =
      parse_condition("all_of(near(cup, work_surface), not(higher(cup, work_surface, 0.1)))");
  EXPECT_TRUE(composed->holds(world)) << composed->explain(world);
  EXPECT_EQ(parse_condition("higher(cup, work_surface, 0.1)")->explain(world),
            "higher(cup, work_surface, 0.1) does not hold");
}

TEST(ConditionRegistration, TheParserChecksItsArityAndArgumentKinds) {
  EXPECT_EQ(parse_error("higher(cup)"),
            "condition 'higher(cup)': higher takes 2 to 3 arguments, not 1");
  EXPECT_EQ(parse_error("higher(cup, box, far)"),
            "condition 'higher(cup, box, far)': higher: argument 3 must be a non-negative "
            "number, not 'far'");
  EXPECT_EQ(parse_error("higher(cup, exists(debris))"),
            "condition 'higher(cup, exists(debris))': higher: argument 2 must be a name");
}

TEST(ConditionRegistration, TheUnknownConditionErrorNamesIt) {
  const std::string error = parse_error("highest(cup)");
  EXPECT_EQ(error.rfind("condition 'highest(cup)': unknown condition 'highest' (known: near, ", 0),
            0u)
      << error;
  EXPECT_NE(error.find(", any_of, higher)"), std::string::npos) << error;
}

TEST(ConditionRegistration, TakenOrMalformedRegistrationsAreRefused) {
  auto refusal = [](ConditionType type) {
    try {
      condition_registry().add(std::move(type));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto make = [](const std::vector<ConditionArg>&) { return exists("cup"); };
  EXPECT_EQ(refusal({"higher", 1, 1, {ConditionArgKind::kName}, make}),
            "condition 'higher' is registered twice");
  EXPECT_EQ(refusal({"near", 1, 1, {ConditionArgKind::kName}, make}),
            "condition 'near' is registered twice");
  EXPECT_EQ(refusal({"two words", 1, 1, {ConditionArgKind::kName}, make}),
            "condition name 'two words' is not 1 to 64 of A-Z a-z 0-9 _");
  EXPECT_EQ(refusal({"kindless", 1, 2, {}, make}),
            "condition 'kindless' takes arguments but declares no argument kinds");
  EXPECT_EQ(refusal({"backwards", 3, 2, {ConditionArgKind::kName}, make}),
            "condition 'backwards': min_args 3 is above max_args 2");
  EXPECT_EQ(refusal({"unmade", 1, 1, {ConditionArgKind::kName}, nullptr}),
            "condition 'unmade' has no make function");
  // None of the refused names became known.
  EXPECT_EQ(condition_registry().names().size(), 11u);
}

}  // namespace
}  // namespace taskmatrix::core
