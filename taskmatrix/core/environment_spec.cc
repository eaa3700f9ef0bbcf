#include "taskmatrix/core/environment_spec.h"

namespace taskmatrix::core {

const char* to_string(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kGraspable:
      return "graspable";
    case ObjectKind::kTool:
      return "tool";
    case ObjectKind::kSurface:
      return "surface";
    case ObjectKind::kDebris:
      return "debris";
  }
  return "?";
}

}  // namespace taskmatrix::core
