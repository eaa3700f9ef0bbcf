#include "harness/results/trial_result.h"

namespace taskmatrix::harness {

namespace {
// A trial's failure reason stays readable: longer ones are cut here, and the whole text is
// in the trial's events (the failed message).
constexpr size_t kMaxReasonChars = 600;
}  // namespace

std::string trial_status(const TrialResult& result) {
  return result.failure ? core::to_string(result.failure->code) : "success";
}

std::string trial_failure_reason(const TrialResult& result) {
  if (!result.failure) return "";
  std::string reason = result.failure->text();
  if (reason.size() <= kMaxReasonChars) return reason;
  reason.resize(kMaxReasonChars);
  return reason + " ... (the whole reason is in the trial's events)";
}

}  // namespace taskmatrix::harness
