#include "harness/trial_record.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "harness/layout_json.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json identity(const RunPlan& plan, const TrialSpec& spec) {
  const Scenario& s = plan.scenarios.at(static_cast<size_t>(spec.scenario));
  const PlannerConfig& p = s.planners.at(static_cast<size_t>(spec.planner));
  nlohmann::json j;
  j["trial_id"] = spec.id;
  j["scenario"] = s.name;
  j["robot"] = spec.robot;
  j["environment"] = spec.environment;
  j["program"] = s.run.program;
  j["planner"] = p.label;
  j["planner_name"] = p.spec.name;
  j["seed"] = spec.seed;
  j["layout_seed"] = spec.layout_seed;
  return j;
}

}  // namespace

nlohmann::json trial_json(const RunPlan& plan, const TrialSpec& spec, const TrialResult& r) {
  nlohmann::json j = identity(plan, spec);
  const mujoco::WorkRecord& w = r.work;
  j["success"] = r.success;
  j["status"] = r.status;
  j["failure_reason"] = r.failure_reason;
  j["planning_time_s"] = w.planning_time_s();
  j["simplification_time_s"] = w.simplification_time_s();
  j["plan_calls"] = w.plans.size();
  j["planner_runs"] = w.planner_runs();
  j["collision_checks"] = w.collision_checks;
  j["ik_calls"] = w.ik_calls;
  j["ik_time_s"] = w.ik_time_s + w.plan_ik_time_s();
  j["path_length_joint"] = w.path_length_joint;
  j["path_length_ee_m"] = w.path_length_ee_m;
  j["duration_s"] = r.duration_s;
  j["sim_time_s"] = r.sim_time_s;
  j["smoothness"] = number_or_null(w.jerk_rms());
  j["min_clearance_m"] = number_or_null(w.min_clearance_m);
  j["clearance_samples"] = w.clearance_samples;
  j["control_periods"] = w.control_periods;
  j["trial_wall_s"] = r.trial_wall_s;
  j["executive_wall_s"] = r.executive_wall_s;
  j["stepping_wall_s"] = w.stepping_wall_s;
  j["monitoring_wall_s"] = w.monitoring_wall_s;
  nlohmann::json events = nlohmann::json::array();
  for (const TrialEvent& e : r.events) {
    nlohmann::json ev = {
        {"t", e.time_s}, {"id", e.sender}, {"program", e.program}, {"type", e.type}};
    if (!e.reason.empty()) ev["reason"] = e.reason;
    if (!e.path.empty()) ev["path"] = e.path;
    events.push_back(std::move(ev));
  }
  j["events"] = std::move(events);
  j["layout"] = layout_json(r.layout);
  nlohmann::json plans = nlohmann::json::array();
  for (const mujoco::PlanCallRecord& p : w.plans) {
    plans.push_back({{"t", p.time_s},
                     {"kind", p.kind},
                     {"status", p.status},
                     {"planner_runs", p.planner_runs},
                     {"planning_time_s", p.planning_time_s},
                     {"simplification_time_s", p.simplification_time_s},
                     {"simplification_hit_time_limit", p.simplification_hit_time_limit},
                     {"ik_time_s", p.ik_time_s},
                     {"collision_checks", p.collision_checks},
                     {"path_length", p.path_length},
                     {"path_states", p.path_states}});
  }
  j["plans"] = std::move(plans);
  j["removed_debris"] = r.removed_debris;
  j["trajectory"] = nullptr;
  return j;
}

nlohmann::json failed_trial_json(const RunPlan& plan, const TrialSpec& spec,
                                 const std::string& status, const std::string& reason) {
  nlohmann::json j = identity(plan, spec);
  j["success"] = false;
  j["status"] = status;
  j["failure_reason"] = reason;
  for (const char* key : {"planning_time_s", "simplification_time_s", "plan_calls", "planner_runs",
                          "collision_checks", "ik_calls", "ik_time_s", "path_length_joint",
                          "path_length_ee_m", "duration_s", "sim_time_s", "smoothness",
                          "min_clearance_m", "clearance_samples", "control_periods", "trial_wall_s",
                          "executive_wall_s", "stepping_wall_s", "monitoring_wall_s"}) {
    j[key] = nullptr;
  }
  j["events"] = nlohmann::json::array();
  j["plans"] = nlohmann::json::array();
  j["removed_debris"] = nlohmann::json::array();
  j["trajectory"] = nullptr;
  return j;
}

const std::vector<std::string>& timing_fields() {
  static const std::vector<std::string> fields = {"planning_time_s",
                                                  "simplification_time_s",
                                                  "ik_time_s",
                                                  "trial_wall_s",
                                                  "executive_wall_s",
                                                  "stepping_wall_s",
                                                  "monitoring_wall_s",
                                                  "wall_time_s",
                                                  "overhead_s",
                                                  "peak_memory_mb",
                                                  "simplification_hit_time_limit"};
  return fields;
}

nlohmann::json without_timing(nlohmann::json trial) {
  for (const std::string& f : timing_fields()) trial.erase(f);
  if (trial.contains("plans")) {
    for (nlohmann::json& p : trial["plans"]) {
      for (const std::string& f : timing_fields()) p.erase(f);
    }
  }
  return trial;
}

TrialsFile read_trials_file(const std::filesystem::path& file) {
  TrialsFile out;
  std::ifstream in(file, std::ios::binary);
  if (!in) return out;
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    ++line;
    const size_t eol = text.find('\n', pos);
    const bool last = eol == std::string::npos || eol + 1 >= text.size();
    const std::string content =
        text.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos);
    nlohmann::json j = nlohmann::json::parse(content, nullptr, /*allow_exceptions=*/false);
    const bool ok =
        eol != std::string::npos && !j.is_discarded() && j.is_object() && j.contains("trial_id");
    if (!ok) {
      if (last) {
        out.torn_tail = true;
        break;
      }
      throw core::InputError(file.string(), "line " + std::to_string(line),
                             "not a trial record (a JSON object with trial_id)");
    }
    out.trials.push_back(std::move(j));
    pos = eol + 1;
    out.valid_bytes = pos;
  }
  return out;
}

}  // namespace taskmatrix::harness
