// What the primitive programs share: limbs by side, mirroring, and plan-then-follow motion
// with the planning messages. Robot-independent: everything comes from the skillset and the
// profile it exposes.
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/task_program.h"
#include "taskmatrix/core/trajectory_follower.h"

namespace taskmatrix::programs {

// The side parameter every limb program takes.
inline const std::vector<std::string> kSides = {"any", "left", "right"};

std::string arm_of(const std::string& side);   // "left" -> "left_arm"
std::string hand_of(const std::string& side);  // "left" -> "left_hand"

// The sides ("left", "right") among `sides` whose `chain_of(side)` is free, in order.
std::vector<std::string> free_sides(const core::ClaimContext& ctx,
                                    const std::vector<std::string>& sides,
                                    std::string (*chain_of)(const std::string&));

// The free side whose palm is nearest to `object`'s grasp point (or the first free side if
// the object is unknown); "left" if no side is free (the executive then refuses the chain).
std::string nearest_free_side(const core::ClaimContext& ctx, const std::string& object,
                              std::string (*chain_of)(const std::string&));

// Joint values for named chains, in a fixed chain order.
struct ChainValues {
  std::vector<std::string> chains;
  std::vector<double> values;  // concatenated in `chains` order
};

// The limb side ("left"/"right") all limb chains of `chains` are on, or "" if they have none
// or are on both sides.
std::string single_side(const std::vector<std::string>& chains);
// The same motion on the other limb: limb chains swapped, joint values times the profile's
// mirror signs. Chains without a side are kept.
ChainValues mirrored(const core::Skillset& skills, const ChainValues& values);
// A posture's values for `only_chains` (empty: every chain it names). A chain the robot may
// lack and does (core::kOptionalChains) is left out, and a list of only such chains gives none.
ChainValues posture_values(const core::Skillset& skills, const std::string& posture,
                           const std::vector<std::string>& only_chains);

// Whether a chain is taken: held by a running program (ClaimContext::busy), or an arm or hand
// whose hand holds an object (a limb carrying something is not free to wave or to rest: its
// hand would open, the object would swing).
bool chain_taken(const core::ClaimContext& ctx, const std::string& chain);

// For programs whose target is a single-limb posture or motion: the version to use, given
// `side` ("any", "left", "right" or "as_named"). With "any": the other limb if the named one
// is taken (chain_taken; or the reverse), the one already at its first values if one is, the one
// whose values touch nothing if only one does (ClaimContext::clear), else one at random. `first`
// gives the values to compare with the current configuration.
struct LimbChoice {
  bool mirror = false;  // use the mirrored values
};
LimbChoice choose_limb(const core::ClaimContext& ctx, const ChainValues& named,
                       const std::string& side);

// Joints within this of a target count as there already (rad or m): no motion is planned.
inline constexpr double kAlreadyThere = 0.02;

// The chains' current configuration clamped to their joint limits (the simulation may rest a
// joint a hair past a limit, which commands may not ask for).
std::vector<double> clamped_configuration(const core::Skillset& skills,
                                          const std::vector<std::string>& chains);

// Largest |a - b| over joints.
double max_difference(const std::vector<double>& a, const std::vector<double>& b);
// A base heading (yaw joint value) within the base's limits: as it is, or, past a limit of a
// yaw whose range spans a full turn, the same heading the other way round; nullopt if neither
// is within them.
std::optional<double> heading_within_limits(const core::ChainInfo& base, double yaw);

// A short straight motion that takes an arm's hand, or what it holds, off what it touches,
// so that a plan can start free: a held object is lifted along the vertical (off the surface
// it rests on), a bare hand withdraws against its approach axis. Computed by IK of the arm
// (or of torso and arm, escape_motion's `torso`) from where it is, keeping the hand's
// orientation; an arm that cannot may turn the hand only if the lowest corner of what it holds
// still rises (a quarter of the lift at least), never tipping it down about the grip. Followed
// slowly, allowed to touch only what it touched.
struct Escape {
  std::vector<std::string> chains;
  core::TimedMotion motion;
  core::ExecutionOptions options;
};
// Whether a finger of the hand on `side` (its segments' origins and a fingertip estimate, as the
// hand is now) lies under a part of `object`: seen from above within 1 cm of one of its shapes
// (its box where perception knows no shapes), that shape's bottom above the finger and less
// than `rise_m` above it. Fingers round a handle: a hand rising would carry the object with it.
bool finger_under(core::ProgramContext& ctx, const std::string& side, const std::string& object,
                  double rise_m);
// What the arm on `side`, its hand or what it holds touches (not the hand itself, not what it
// holds), by name.
std::vector<std::string> touched_by_arm(core::ProgramContext& ctx, const std::string& side);
// The escape for the arm on `side` if its hand or held object touches something (`touched`:
// touched_by_arm's answer now), or always with `always`; nullopt when nothing is touched or
// the arm cannot move that way. `distance_m`: how far. A straight lift in two steps, each a
// short joint motion; where IK reaches the lifted hand only in another posture of the arm, a
// planned motion to a collision-free one. With `torso` (the caller holds the torso, if the
// robot has one), where the arm alone finds no such motion, torso and arm together. With
// `lift`, a bare hand rises along the vertical too: off an object it has let go of, which
// stands on a surface between its fingers (withdrawn against the approach axis, fingers
// still round the object's far side would drag it along).
std::optional<Escape> escape_motion(core::ProgramContext& ctx, const std::string& side,
                                    const std::vector<std::string>& touched, double distance_m,
                                    bool always = false, bool torso = false, bool lift = false);

// How a motion ended: nullopt when it completed, else its failure.
using Ended = std::optional<core::Failure>;

// Plans a motion (emitting planning_started and planning_ended with the plan) and follows it
// one control period per step() call. When an arm among the planned chains starts against
// something (its hand around what it let go of, what it holds on the surface it rests on), the
// stage first follows that arm's escape motion, then plans from there.
class MotionStage {
 public:
  // Each returns nullopt when following has started, else why it did not.
  std::optional<core::Failure> plan_to_configuration(core::ProgramContext& ctx,
                                                     const std::vector<std::string>& chains,
                                                     const std::vector<double>& goal);
  // The same without the escape: plans from where the chains are now.
  std::optional<core::Failure> plan_now(core::ProgramContext& ctx,
                                        const std::vector<std::string>& chains,
                                        const std::vector<double>& goal);
  // Follows without planning.
  void follow(core::ProgramContext& ctx, const std::vector<std::string>& chains,
              core::TimedMotion motion, const core::ExecutionOptions& options = {});
  // nullopt while moving; once ended, its failure (nullopt when it completed).
  std::optional<Ended> step();
  const core::PlanResult* last_plan() const { return plan_.get(); }
  // Adds names to execution.may_touch (once each): what a motion started against them may touch.
  void allow_touching(const std::vector<std::string>& names);
  // How planned motions are followed (tolerance at the end, settling time, what they may touch;
  // the plans' start may touch that too).
  core::ExecutionOptions execution;

 private:
  std::optional<core::Failure> start_following(core::ProgramContext& ctx,
                                               const std::vector<std::string>& chains,
                                               std::shared_ptr<const core::PlanResult> plan);
  std::shared_ptr<const core::PlanResult> plan_;
  std::optional<core::TrajectoryFollower> follower_;
  // A plan waiting for an escape motion to end.
  core::ProgramContext* pending_ctx_ = nullptr;
  std::vector<std::string> pending_chains_;
  std::vector<double> pending_goal_;
};

// A target for an arm's frame: a pose, and a world axis through it about which the task lets
// the frame turn (an upright cup held anywhere round, a tool held at any heading) and how far.
struct ArmTarget {
  core::Pose pose;
  Eigen::Vector3d free_axis = Eigen::Vector3d::Zero();  // world; zero: the full pose
  double free_turn_rad = 0;                             // M_PI or more: any turn
  std::string tag;                                      // what the target is, for messages
  // Points in the frame's coordinates that must stay above the world height `floor_z` at a
  // solution, however the frame turned about `free_axis` (the points a closing hand's fingers
  // sweep through, over the surface the object stands on); empty: none.
  std::vector<Eigen::Vector3d> keep_above;
  double floor_z = -INFINITY;
};

// How far a frame moved by a body (base, torso, arm) gets from the base's vertical axis, at
// any height: the largest of uniform draws over the joint limits (base held), each of the
// farthest then pushed outwards joint by joint. A search, so a lower estimate of the true
// farthest reach (a stance search adds a slack), computed once per stance search.
class ReachEnvelope {
 public:
  ReachEnvelope(core::Skillset& skills, const std::vector<std::string>& body,
                const std::string& frame);
  double radius() const { return radius_; }
  // Where the base's vertical axis is (world x, y) with the base's joints at zero.
  const Eigen::Vector2d& axis_at_origin() const { return axis_; }
  static constexpr int kDraws = 400;
  static constexpr int kClimbs = 4;
  // How much farther than radius() a target may be for a stance search to try a base pose:
  // more than the search falls short of the true farthest reach.
  static constexpr double kSlackM = 0.05;

 private:
  double radius_ = 0;
  Eigen::Vector2d axis_ = Eigen::Vector2d::Zero();
};

// Failures of finding a way to a target: no IK solution, or none the planner could connect to
// (the arm at the edge of its workspace). A stance nearer the target, or other targets, may
// cure them.
bool found_no_way(const core::Failure& failure);

// Moves `frame` of an arm to one of `targets` (tried in order) with as little of the body as
// will do: the arm; when IK finds no solution for any target, torso and arm (if `torso`); then
// (if `base`) the robot steps: IK over base, torso and arm gives a stance from which the arm
// reaches, the base alone is planned there and driven (locomotion through the planar base
// joints), and torso and arm are planned from the new stance; where they cannot reach or be
// planned from there, the robot steps again, to a stance away from those that failed (at most
// kMaxFailedStances of them). Where the whole body finds no way to a stance in one motion,
// torso and arm are drawn in first and the base walks there with them so (carry_to_stance);
// where every plan from the start failed with the hand a hair off something, the hand is
// lifted straight off once and reaching starts again (lift_first). The frame may be a held
// object's (a tool's tip): every stage moves the hand holding it. An arm that starts against
// something escapes first (escape_motion).
class ArmMotion {
 public:
  // nullopt when moving, else why it is not.
  std::optional<core::Failure> start(core::ProgramContext& ctx, const std::string& arm,
                                     const std::string& frame, std::vector<ArmTarget> targets,
                                     const core::IkOptions& ik, bool torso, bool base);
  // As MotionStage::step.
  std::optional<Ended> step(core::ProgramContext& ctx);
  MotionStage& stage() { return motion_; }
  // The target being moved to (after start succeeded); -1 if none.
  int target_index() const { return reached_; }

 private:
  enum class Phase { kEscaping, kCarrying, kStepping, kReaching };
  std::optional<core::Failure> reach_from_here(core::ProgramContext& ctx);
  // `failure`: why reaching from here failed. Stances near one in stances_left_ are not tried.
  std::optional<core::Failure> step_over(core::ProgramContext& ctx, core::Failure failure);
  // True if the base pose (x, y, yaw) is near a stance reaching already failed from.
  bool left_before(const std::vector<double>& base) const;
  // Base poses to search for a stance: near the current one, then round the targets; the
  // nearest travel first; repeats and poses from which every target is out of the frame's
  // reach (ReachEnvelope) dropped.
  std::vector<std::vector<double>> stance_candidates(core::ProgramContext& ctx,
                                                     const std::vector<std::string>& body);
  // Moves to a whole-body solution for target k: the base first when the rest of the body can
  // stay as it is meanwhile.
  std::optional<core::Failure> go_to_stance(core::ProgramContext& ctx,
                                            const std::vector<std::string>& body, size_t k,
                                            const std::vector<double>& solution);
  // After reaching from here found no way (a plan failed): when the hand or what it holds is
  // within the planner's clearance of something, starts lifting it straight off (once per
  // start), after which reaching is tried again; false if it does not.
  bool lift_first(core::ProgramContext& ctx, const core::Failure& failure);
  // When the whole body found no way to the solution in one motion: starts drawing torso and
  // arm in to a posture clear both here and at the stance, from which the base walks there
  // (kCarrying, then kStepping); false if no such posture could be planned to.
  bool carry_to_stance(core::ProgramContext& ctx, const std::vector<std::string>& body, size_t k,
                       const std::vector<double>& solution);
  // IK of `chains` for target k (with `options`, else the program's), keeping solutions
  // within its free turn.
  std::vector<std::vector<double>> solve(core::ProgramContext& ctx,
                                         const std::vector<std::string>& chains, size_t k,
                                         std::string& why,
                                         const core::IkOptions* options = nullptr);
  // The stance search's work bounds: stances tried, and IK restarts per target at each.
  static constexpr int kMaxStances = 48;
  static constexpr int kStanceRestarts = 3;
  // The second pass: stances searched with the base free, and its IK weight there.
  static constexpr int kMaxLooseStances = 24;
  static constexpr double kLooseBaseWeight = 0.1;
  // The third pass, when the first two found nothing: the nearest stances again, base held,
  // with this many IK restarts per target.
  static constexpr int kMaxRefinedStances = 8;
  static constexpr int kRefineRestarts = 16;
  // Stances found that the planner could not get to before the search gives up.
  static constexpr int kMaxUnplannedStances = 3;
  // Plans tried to draw torso and arm in before carrying them to a stance (carry_to_stance).
  static constexpr int kMaxCarryPlans = 2;
  // A carrying posture this close (max-norm, rad or m) to the current one is that one.
  static constexpr double kSameCarryRad = 0.01;
  // Stances stepped to from which the arm's plan then failed, before the failure is the
  // program's; and how near another stance must be to one of them to count as the same.
  static constexpr int kMaxFailedStances = 2;
  static constexpr double kFailedStanceM = 0.1;
  static constexpr double kFailedStanceRad = 0.3;
  // Stances on each ring round the target, and what a turn of the base costs against walking
  // when ordering them (metres per radian).
  static constexpr int kStanceHeadings = 12;
  static constexpr double kStanceTurnCostM = 0.3;
  // Candidates this close (metres apart, and radians of heading) are the same stance.
  static constexpr double kSameStanceM = 0.01;
  static constexpr double kSameStanceRad = 0.01;
  MotionStage motion_;
  std::string arm_, frame_;
  std::vector<ArmTarget> targets_;
  core::IkOptions ik_;
  bool torso_ = false, base_ = false;
  Phase phase_ = Phase::kReaching;
  int reached_ = -1;
  // While stepping: the target the stance is for, and the rest of the body's values there.
  int stance_target_ = -1;
  std::vector<double> stance_rest_;
  std::vector<double> stance_base_;       // while carrying: the base pose to walk to
  std::vector<std::string> stance_body_;  // base, torso (if used) and arm
  bool lifted_ = false;                   // lift_first has lifted the hand
  // Base poses of the stances stepped to from which reaching failed.
  std::vector<std::vector<double>> stances_left_;
  // The best IK miss over the targets, for the failure message.
  double best_miss_m_ = INFINITY, best_miss_rad_ = 0;
  std::string best_miss_tag_;
};

// The chains an arm program claims: the arm, and the torso (a robot may have none) and base
// when allowed and free.
std::vector<std::string> arm_claim(const core::ClaimContext& ctx, const std::string& arm,
                                   bool& torso, bool& base);

// The robot's head chain, or nothing for a robot whose head camera is fixed to its trunk.
std::vector<std::string> head_chains(const core::Skillset& skills);

// The chains a head program claims: the head (if the robot has one), and the base when
// allowed and free.
std::vector<std::string> head_claim(const core::ClaimContext& ctx, bool& base);

// The failure of a failed plan: its status's code and its message.
core::Failure plan_failure(const core::PlanResult& plan);

}  // namespace taskmatrix::programs
