#include "taskmatrix/mujoco/work_record.h"

#include <cmath>

namespace taskmatrix::mujoco {

double WorkRecord::planning_time_s() const {
  double t = 0;
  for (const PlanCallRecord& p : plans) t += p.planning_time_s;
  return t;
}

double WorkRecord::simplification_time_s() const {
  double t = 0;
  for (const PlanCallRecord& p : plans) t += p.simplification_time_s;
  return t;
}

double WorkRecord::plan_ik_time_s() const {
  double t = 0;
  for (const PlanCallRecord& p : plans) t += p.ik_time_s;
  return t;
}

int WorkRecord::planner_runs() const {
  int n = 0;
  for (const PlanCallRecord& p : plans) n += p.planner_runs;
  return n;
}

double WorkRecord::jerk_rms() const {
  return jerk_samples > 0 ? std::sqrt(jerk_squared_sum / static_cast<double>(jerk_samples)) : NAN;
}

}  // namespace taskmatrix::mujoco
