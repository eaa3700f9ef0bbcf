// Why a program, or a whole trial, failed: a code from one fixed list, a detail for a person,
// and where inside nested state machines it happened. Programs, the executive and the
// harness branch on the code; its text ("ik_failure") appears only where a failure is
// written out (messages' text, trial records, logs), through to_string and
// failure_code_from_string here.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/core/skillset.h"

namespace taskmatrix::core {

// The statuses of a failed trial. The first ones keep the order of the trial-status enum in
// the Planner Arena log (harness/results/ompl_log.cc), whose indices logs of different runs share:
// add new codes at the end.
enum class FailureCode {
  kCrash,                // the runner's: the worker died (a signal, mju_error, ...)
  kTimeout,              // the runner's: killed at the scenario's wall_limit_s
  kSimUnstable,          // the simulator diverged
  kSetupFailed,          // a scenario's set-up program failed (the detail says how)
  kTimeLimit,            // the program still ran at the scenario's time_limit_s
  kCriterionFalse,       // completed, but the success condition does not hold
  kPlanningTimeout,      // the planner used its budget without a path
  kIkFailure,            // no configuration places the frame at any target
  kCollision,            // a moving part touched what it may not
  kGraspFailed,          // the grasps tried did not hold
  kInvalidStart,         // the plan's start is in collision or outside limits
  kInvalidGoal,          // every goal is in collision or outside limits, or none exists
  kInvalidInput,         // a program's arguments or a request do not make sense
  kPreconditionFalse,    // the program's precondition did not hold at its start
  kInvariantFalse,       // a state machine's state invariant stopped holding
  kNoTransition,         // a state machine's state ended and no transition took it on
  kPerceptionMiss,       // an object the program needs is not in the perceptual model
  kNotGraspable,         // the hand cannot hold the object
  kCoverageShort,        // explore observed less than it had to
  kChainsBusy,           // a chain the program needs is held by another program
  kApproximateSolution,  // the planner's path ends near, not at, the goal
  kTrackingError,        // the motion did not settle within tolerance of its end
  kProgramError,         // the program threw (or ended without saying why)
  kPlanningFailed,       // the planner stopped without a path before its budget was spent
  kFailureState,         // a state machine ended in a final state that is not a success
};

// Every code, in declaration order.
const std::vector<FailureCode>& all_failure_codes();
// "ik_failure", ...
const char* to_string(FailureCode code);
// The code of a text written by to_string; nullopt for any other text.
std::optional<FailureCode> failure_code_from_string(std::string_view text);

// The failure of a plan (any status but kExactSolution) or of an execution (any status but
// kCompleted).
FailureCode failure_code(PlanStatus status);
FailureCode failure_code(ExecutionStatus status);

struct Failure {
  Failure() = default;
  Failure(FailureCode what, std::string why, std::string where = "")
      : code(what), detail(std::move(why)), path(std::move(where)) {}

  FailureCode code = FailureCode::kProgramError;
  std::string detail;  // what happened, for a person
  // For a failure inside state machines: where, as "state-program(state) > ..." down to the
  // program that failed, e.g. "greet > postural(lower)"; empty when the failing program is the
  // one that reports it.
  std::string path;

  // "<code>: <detail>", e.g. "ik_failure: palm reaches none of 3 targets ...".
  std::string reason() const;
  // As a user reads it: "<path>: <reason>", or the reason alone without a path.
  std::string text() const;
  bool operator==(const Failure& other) const = default;
};

// `failure` as reported by `program`, which ran the machine it happened in: its path begins
// with the program ("tidy > greet > postural(lower)"); unchanged when it has no path (the
// program failed itself).
Failure reported_by(const std::string& program, Failure failure);

}  // namespace taskmatrix::core
