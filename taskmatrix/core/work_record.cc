#include "taskmatrix/core/work_record.h"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace taskmatrix::core {

namespace {

template <typename T>
T sum_over(const std::vector<PlanCallRecord>& plans, T PlanCallRecord::*field) {
  T total{};
  for (const PlanCallRecord& p : plans) total += p.*field;
  return total;
}

}  // namespace

std::string path_digest(const std::vector<std::vector<double>>& path) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::vector<double>& q : path) {
    for (double v : q) {
      unsigned char bytes[sizeof v];
      std::memcpy(bytes, &v, sizeof v);
      for (unsigned char b : bytes) h = (h ^ b) * 0x100000001b3ULL;
    }
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

double WorkRecord::planning_time_s() const {
  return sum_over(plans, &PlanCallRecord::planning_time_s);
}

double WorkRecord::simplification_time_s() const {
  return sum_over(plans, &PlanCallRecord::simplification_time_s);
}

double WorkRecord::plan_ik_time_s() const { return sum_over(plans, &PlanCallRecord::ik_time_s); }

int WorkRecord::planner_runs() const { return sum_over(plans, &PlanCallRecord::planner_runs); }

double WorkRecord::jerk_rms() const {
  return jerk_samples > 0 ? std::sqrt(jerk_squared_sum / static_cast<double>(jerk_samples)) : NAN;
}

}  // namespace taskmatrix::core
