#include "taskmatrix/core/planning_types.h"

#include "taskmatrix/core/failure.h"

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
  // A failed plan's status reads as the failure it causes ("planning_timeout").
  if (status == PlanStatus::kExactSolution) return "exact_solution";
  return to_string(failure_code(status));
}

}  // namespace taskmatrix::core
