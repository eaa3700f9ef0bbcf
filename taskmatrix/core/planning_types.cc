#include "taskmatrix/core/planning_types.h"

namespace taskmatrix::core {

const char* to_string(IkStatus status) {
  switch (status) {
    case IkStatus::kSolved:
      return "solved";
    case IkStatus::kUnreachable:
      return "unreachable";
    case IkStatus::kInCollision:
      return "in_collision";
    case IkStatus::kInvalidInput:
      return "invalid_input";
  }
  return "?";
}

const char* to_string(PlanStatus status) {
  switch (status) {
    case PlanStatus::kExactSolution:
      return "exact_solution";
    case PlanStatus::kApproximateSolution:
      return "approximate_solution";
    case PlanStatus::kTimeout:
      return "planning_timeout";
    case PlanStatus::kInvalidStart:
      return "invalid_start";
    case PlanStatus::kInvalidGoal:
      return "invalid_goal";
    case PlanStatus::kIkFailure:
      return "ik_failure";
    case PlanStatus::kInvalidInput:
      return "invalid_input";
  }
  return "?";
}

}  // namespace taskmatrix::core
