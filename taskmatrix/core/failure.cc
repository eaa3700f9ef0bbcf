#include "taskmatrix/core/failure.h"

#include <array>
#include <utility>

namespace taskmatrix::core {

namespace {

struct CodeName {
  FailureCode code;
  const char* name;
};

// The one place failure codes are spelled.
constexpr std::array kCodeNames = {
    CodeName{FailureCode::kCrash, "crash"},
    CodeName{FailureCode::kTimeout, "timeout"},
    CodeName{FailureCode::kSimUnstable, "sim_unstable"},
    CodeName{FailureCode::kSetupFailed, "setup_failed"},
    CodeName{FailureCode::kTimeLimit, "time_limit"},
    CodeName{FailureCode::kCriterionFalse, "criterion_false"},
    CodeName{FailureCode::kPlanningTimeout, "planning_timeout"},
    CodeName{FailureCode::kIkFailure, "ik_failure"},
    CodeName{FailureCode::kCollision, "collision"},
    CodeName{FailureCode::kGraspFailed, "grasp_failed"},
    CodeName{FailureCode::kInvalidStart, "invalid_start"},
    CodeName{FailureCode::kInvalidGoal, "invalid_goal"},
    CodeName{FailureCode::kInvalidInput, "invalid_input"},
    CodeName{FailureCode::kPreconditionFalse, "precondition_false"},
    CodeName{FailureCode::kInvariantFalse, "invariant_false"},
    CodeName{FailureCode::kNoTransition, "no_transition"},
    CodeName{FailureCode::kPerceptionMiss, "perception_miss"},
    CodeName{FailureCode::kNotGraspable, "not_graspable"},
    CodeName{FailureCode::kCoverageShort, "coverage_short"},
    CodeName{FailureCode::kChainsBusy, "chains_busy"},
    CodeName{FailureCode::kApproximateSolution, "approximate_solution"},
    CodeName{FailureCode::kTrackingError, "tracking_error"},
    CodeName{FailureCode::kProgramError, "program_error"},
    CodeName{FailureCode::kPlanningFailed, "planning_failed"},
    CodeName{FailureCode::kFailureState, "failure_state"},
};

// Declaration order, checked at compile time: the table holds every code once, in order.
constexpr bool in_declaration_order() {
  for (size_t i = 0; i < kCodeNames.size(); ++i) {
    if (static_cast<size_t>(kCodeNames[i].code) != i) return false;
  }
  return true;
}
static_assert(in_declaration_order(), "kCodeNames must list every FailureCode in order");
static_assert(static_cast<size_t>(FailureCode::kFailureState) + 1 == kCodeNames.size(),
              "kCodeNames must list every FailureCode");

}  // namespace

const std::vector<FailureCode>& all_failure_codes() {
  static const std::vector<FailureCode> codes = [] {
    std::vector<FailureCode> out;
    for (const CodeName& c : kCodeNames) out.push_back(c.code);
    return out;
  }();
  return codes;
}

const char* to_string(FailureCode code) {
  const auto i = static_cast<size_t>(code);
  return i < kCodeNames.size() ? kCodeNames[i].name : "unknown";
}

std::optional<FailureCode> failure_code_from_string(std::string_view text) {
  for (const CodeName& c : kCodeNames) {
    if (text == c.name) return c.code;
  }
  return std::nullopt;
}

FailureCode failure_code(PlanStatus status) {
  switch (status) {
    case PlanStatus::kApproximateSolution:
      return FailureCode::kApproximateSolution;
    case PlanStatus::kTimeout:
      return FailureCode::kPlanningTimeout;
    case PlanStatus::kPlanningFailed:
      return FailureCode::kPlanningFailed;
    case PlanStatus::kInvalidStart:
      return FailureCode::kInvalidStart;
    case PlanStatus::kInvalidGoal:
      return FailureCode::kInvalidGoal;
    case PlanStatus::kIkFailure:
      return FailureCode::kIkFailure;
    case PlanStatus::kExactSolution:  // not a failure: a caller's mistake
    case PlanStatus::kInvalidInput:
      return FailureCode::kInvalidInput;
  }
  return FailureCode::kInvalidInput;
}

FailureCode failure_code(ExecutionStatus status) {
  switch (status) {
    case ExecutionStatus::kCollision:
      return FailureCode::kCollision;
    case ExecutionStatus::kTrackingError:
      return FailureCode::kTrackingError;
    case ExecutionStatus::kSimulationUnstable:
      return FailureCode::kSimUnstable;
    case ExecutionStatus::kCompleted:  // not a failure: a caller's mistake
    case ExecutionStatus::kInvalidInput:
      return FailureCode::kInvalidInput;
  }
  return FailureCode::kInvalidInput;
}

std::string Failure::reason() const { return std::string(to_string(code)) + ": " + detail; }

std::string Failure::text() const { return path.empty() ? reason() : path + ": " + reason(); }

Failure reported_by(const std::string& program, Failure failure) {
  if (!failure.path.empty()) failure.path = program + " > " + failure.path;
  return failure;
}

}  // namespace taskmatrix::core
