// Conditions (paper section III-C): Boolean predicates over the robot (through the skillset)
// and the perceptual model, composable with all_of / any_of / negate. They are used as
// program preconditions and, for object placement, as generators of states that satisfy
// them (putdown draws placements from above(object, surface) and near(object, surface)).
//
// Definitions:
//   near(A, B, d)         the bounding boxes of A and B are at most d apart (default 0.10 m)
//   above(A, B)           the ground projections of the boxes intersect and A's bottom is no
//                         lower than B's top minus 2 cm
//   postural(C, P, tol)   every joint of chains C (default: the chains P names) is within tol
//                         (default 0.05 rad or m) of posture P
//   grasping(A)           A is held by a hand (attached through the skillset)
//   graspable(A, side)    A is known, not held, and the palm of `side` ("left", "right" or
//                         "any") is within 3 cm of A's grasp point (PerceivedObject::grasp_point)
//                         or, for an object without a grip frame, inside A's box
//   in_view(A)            part of A's box is inside the head camera's field of view and the
//                         sensor's range: one of 27 points (corners, edge and face centres,
//                         centre) is (nothing about occlusion)
//   exists(T)             the perceptual model knows an object of type T ("debris", ...)
// An object the perceptual model does not know makes near/above/graspable/in_view false.
//
// Text form (scenario success criteria, state-machine guards and invariants), parsed by
// parse_condition: the names above (and any registered: ConditionRegistry below) as calls,
// with not/all_of/any_of for composition, e.g.
//   all_of(above(cup, side_surface), near(cup, side_surface, 0.1), not(grasping(cup)))
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/skillset.h"

namespace taskmatrix::core {

struct World {
  Skillset& skills;
  const PerceptualModel& percepts;
};

// "What if object `id` had this box": for testing candidate placements.
struct Hypothesis {
  std::string id;
  Eigen::AlignedBox3d box;
};

class Condition {
 public:
  virtual ~Condition() = default;
  virtual bool holds(const World& world, const Hypothesis* hypothesis = nullptr) const = 0;
  virtual std::string describe() const = 0;
  // Why the condition does not hold now, naming the clause that fails and what was measured
  // ("above(cup, side_surface): cup's bottom is 4.1 cm below side_surface's top"); for a
  // condition that holds, describe() + " holds".
  virtual std::string explain(const World& world) const;
  // A box for `object` that satisfies this condition, drawn with `rng`, if this condition
  // can propose one; conjunctions draw from their generating members and keep draws for
  // which every member holds.
  virtual std::optional<Eigen::AlignedBox3d> propose(const World& world, const std::string& object,
                                                     std::mt19937_64& rng) const;
};
using ConditionPtr = std::shared_ptr<const Condition>;

ConditionPtr near(std::string a, std::string b, double distance_m = 0.10);
ConditionPtr above(std::string a, std::string b);
ConditionPtr postural(std::string posture, std::vector<std::string> chains = {},
                      double tolerance = 0.05);
ConditionPtr grasping(std::string object);
ConditionPtr graspable(std::string object, std::string side = "any");
ConditionPtr in_view(std::string object);
ConditionPtr exists(std::string type);
ConditionPtr all_of(std::vector<ConditionPtr> conditions);
ConditionPtr any_of(std::vector<ConditionPtr> conditions);
ConditionPtr negate(ConditionPtr condition);

// ---- The condition registry: what the text form may call.
// A call's arguments are names (types, postures, chains, sides: any WORD of the text form),
// object names (a WORD naming a thing the perceptual model knows, which `taskmatrix validate`
// and `run` check against every environment of a scenario), non-negative finite numbers, or
// nested conditions.
enum class ConditionArgKind { kName, kObject, kNumber, kCondition };

// One parsed argument: `name` for kName and kObject, `number` for kNumber, `condition` for
// kCondition.
struct ConditionArg {
  std::string name;
  double number = 0;
  ConditionPtr condition;
};

// max_args for a condition that takes any number of arguments from min_args on.
inline constexpr size_t kAnyNumberOfArgs = static_cast<size_t>(-1);

struct ConditionType {
  std::string name;  // 1 to 64 of [A-Za-z0-9_]
  size_t min_args = 0, max_args = 0;
  // The kind of each argument by position; positions past the end take the last kind.
  std::vector<ConditionArgKind> kinds;
  // Called with min_args to max_args arguments of the declared kinds (the parser has checked
  // both); fills in defaults for the arguments left out.
  std::function<ConditionPtr(const std::vector<ConditionArg>&)> make;
};

class ConditionRegistry {
 public:
  // Throws std::invalid_argument for a taken or malformed name, arities that do not make
  // sense, no argument kinds where arguments are taken, or no make.
  void add(ConditionType type);
  const ConditionType* find(const std::string& name) const;
  // In the order they were added: the built-ins in the order of docs/conditions.md, then any
  // a program adds.
  std::vector<std::string> names() const;

 private:
  std::vector<ConditionType> types_;
};

// The process's registry: the built-in conditions above, and any registered since.
ConditionRegistry& condition_registry();

// Adds a condition to condition_registry() when the program starts, so a user's condition is
// one file of the executable that uses it (a static library's unreferenced file is dropped by
// the linker: list the file in the executable's sources):
//   static const ConditionRegistration kTaller{{"taller", 2, 2, {ConditionArgKind::kObject},
//       [](const std::vector<ConditionArg>& a) { return taller(a[0].name, a[1].name); }}};
// Throws (ending the program at start) what ConditionRegistry::add throws.
struct ConditionRegistration {
  explicit ConditionRegistration(ConditionType type);
};

// Parses the text form with `registry`'s conditions. Throws std::invalid_argument naming the
// position and what was expected ("condition 'near(cup)': near takes 2 to 3 arguments, not
// 1"; an unknown name lists the known ones), also for conditions nested more than
// kMaxConditionDepth calls deep.
inline constexpr int kMaxConditionDepth = 64;
ConditionPtr parse_condition(const std::string& text,
                             const ConditionRegistry& registry = condition_registry());
// The words `text` passes as kObject arguments, in order, repeats kept (a "$name" of a
// machine's condition as written). Parses as parse_condition does and throws as it does.
std::vector<std::string> condition_object_names(
    const std::string& text, const ConditionRegistry& registry = condition_registry());

// Whether `point` (world) is inside the head camera's field of view and range now; for a box,
// whether one of its 27 corner, edge-centre, face-centre and centre points is.
bool in_camera_view(Skillset& skills, const Eigen::Vector3d& point);
bool in_camera_view(Skillset& skills, const Eigen::AlignedBox3d& box);

// Up to `count` boxes for `object` satisfying `condition`, from at most `max_draws` draws.
std::vector<Eigen::AlignedBox3d> sample_placements(const Condition& condition, const World& world,
                                                   const std::string& object, std::mt19937_64& rng,
                                                   int count, int max_draws = 500);

// The distance between two boxes (0 if they overlap).
double box_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b);

}  // namespace taskmatrix::core
