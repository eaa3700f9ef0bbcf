#include "harness/results/trial_record.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/results/json_input.h"
#include "harness/results/layout_json.h"
#include "harness/results/trial_schema.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

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
  j["execution"] = s.execution;
  j["seed"] = spec.seed;
  j["layout_seed"] = spec.layout_seed;
  return j;
}

}  // namespace

nlohmann::json trial_json(const RunPlan& plan, const TrialSpec& spec, const TrialResult& r) {
  nlohmann::json j = identity(plan, spec);
  const core::WorkRecord& w = r.work;
  j["success"] = r.success;
  j["status"] = trial_status(r);
  j["failure_reason"] = trial_failure_reason(r);
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
  j["contacts_per_pass"] = w.contact_passes > 0
                               ? nlohmann::json(static_cast<double>(w.contacts) / w.contact_passes)
                               : nlohmann::json(nullptr);
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
  for (const core::PlanCallRecord& p : w.plans) {
    plans.push_back({{"t", p.time_s},
                     {"kind", p.kind},
                     {"status", p.status},
                     {"planner_runs", p.planner_runs},
                     {"planning_time_s", p.planning_time_s},
                     {"simplification_time_s", p.simplification_time_s},
                     {"planning_hit_time_limit", p.planning_hit_time_limit},
                     {"simplification_hit_time_limit", p.simplification_hit_time_limit},
                     {"planner_iterations", p.planner_iterations},
                     {"ik_time_s", p.ik_time_s},
                     {"collision_checks", p.collision_checks},
                     {"path_length", p.path_length},
                     {"path_states", p.path_states},
                     {"path_digest", p.path_digest}});
  }
  j["plans"] = std::move(plans);
  j["clock_bound_hit"] = clock_bounds_hit(j);
  j["removed_debris"] = r.removed_debris;
  j["trajectory"] = nullptr;
  return j;
}

nlohmann::json failed_trial_json(const RunPlan& plan, const TrialSpec& spec,
                                 const core::Failure& failure) {
  nlohmann::json j = identity(plan, spec);
  j["success"] = false;
  j["status"] = core::to_string(failure.code);
  j["failure_reason"] = failure.text();
  // Nothing was measured: null, never 0.
  for (const TrialField& f : kTrialFields) {
    if (f.source == FieldSource::kMeasured) j[std::string(f.name)] = nullptr;
  }
  j["events"] = nlohmann::json::array();
  j["plans"] = nlohmann::json::array();
  j["removed_debris"] = nlohmann::json::array();
  j["trajectory"] = nullptr;
  j["clock_bound_hit"] = clock_bounds_hit(j);
  return j;
}

std::vector<std::string> clock_bounds_hit(const nlohmann::json& trial) {
  std::vector<std::string> hit;
  auto add = [&](const std::string& what) {
    if (std::find(hit.begin(), hit.end(), what) == hit.end()) hit.push_back(what);
  };
  const auto recorded = trial.find("clock_bound_hit");
  if (recorded != trial.end() && recorded->is_array()) {
    for (const nlohmann::json& w : *recorded) add(w.is_string() ? w.get<std::string>() : w.dump());
  }
  const auto plans = trial.find("plans");
  if (plans != trial.end() && plans->is_array()) {
    for (const nlohmann::json& p : *plans) {
      if (!p.is_object()) continue;
      auto flag = [&p](const char* key) {
        const auto it = p.find(key);
        return it != p.end() && it->is_boolean() && it->get<bool>();
      };
      if (flag("planning_hit_time_limit")) add("plan_time_limit");
      if (flag("simplification_hit_time_limit")) add("simplify_time_limit");
    }
  }
  const auto status = trial.find("status");
  if (status != trial.end() && status->is_string() &&
      core::failure_code_from_string(status->get<std::string>()) == core::FailureCode::kTimeout) {
    add("wall_limit");
  }
  return hit;
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

void check_trial_record(const nlohmann::json& t, const JsonPlace& where) {
  if (!t.is_object()) where.fail("must be a JSON object (a trial record)");
  for (const char* key :
       {"trial_id", "scenario", "program", "robot", "environment", "planner", "status"}) {
    json_field(t, key, JsonKind::kString, where);
  }
  json_field(t, "success", JsonKind::kBool, where);
  json_field(t, "seed", JsonKind::kUnsigned, where);
  json_field(t, "layout_seed", JsonKind::kUnsigned, where);
  for (const char* key : {"failure_reason", "planner_name"}) {
    json_optional_field(t, key, JsonKind::kString, where);
  }
  for (const char* key : {"plan_calls", "planner_runs", "collision_checks", "ik_calls",
                          "clearance_samples", "control_periods", "trajectory_frames"}) {
    json_optional_field(t, key, JsonKind::kUnsigned, where);
  }
  for (const char* key :
       {"planning_time_s", "simplification_time_s", "ik_time_s", "path_length_joint",
        "path_length_ee_m", "duration_s", "sim_time_s", "smoothness", "min_clearance_m",
        "trial_wall_s", "executive_wall_s", "stepping_wall_s", "monitoring_wall_s", "wall_time_s",
        "overhead_s", "peak_memory_mb"}) {
    json_optional_field(t, key, JsonKind::kNumber, where);
  }
  for (const char* key : {"events", "removed_debris", "clock_bound_hit"}) {
    json_optional_field(t, key, JsonKind::kArray, where);
  }
  const nlohmann::json& hit = json_optional_field(t, "clock_bound_hit", JsonKind::kArray, where);
  for (size_t i = 0; hit.is_array() && i < hit.size(); ++i) {
    if (!hit[i].is_string())
      where.at("clock_bound_hit[" + std::to_string(i) + "]").fail("must be a string");
  }
  const nlohmann::json& plans = json_optional_field(t, "plans", JsonKind::kArray, where);
  for (size_t i = 0; plans.is_array() && i < plans.size(); ++i) {
    const JsonPlace p = where.at("plans[" + std::to_string(i) + "]");
    if (!plans[i].is_object()) p.fail("must be an object");
    for (const char* key : {"planning_hit_time_limit", "simplification_hit_time_limit"}) {
      json_optional_field(plans[i], key, JsonKind::kBool, p);
    }
    for (const char* key :
         {"collision_checks", "planner_runs", "planner_iterations", "path_states"}) {
      json_optional_field(plans[i], key, JsonKind::kUnsigned, p);
    }
    for (const char* key :
         {"t", "planning_time_s", "simplification_time_s", "ik_time_s", "path_length"}) {
      json_optional_field(plans[i], key, JsonKind::kNumber, p);
    }
  }
  // A recorded trajectory lies inside the run directory.
  const nlohmann::json& traj = json_optional_field(t, "trajectory", JsonKind::kString, where);
  if (traj.is_string()) {
    const std::filesystem::path rel = traj.get<std::string>();
    bool inside = rel.is_relative() && !rel.empty();
    for (const auto& part : rel) inside = inside && part != "..";
    if (!inside) where.at("trajectory").fail("must be a path inside the run directory");
  }
}

TrialsFile read_trials_file(const std::filesystem::path& file) {
  TrialsFile out;
  std::ifstream in(file, std::ios::binary);
  if (!in) return out;
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::map<std::string, int> line_of_id;
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
      // A killed run may leave its last line unfinished; anything else is not ours.
      if (last && (eol == std::string::npos || j.is_discarded())) {
        out.torn_tail = true;
        break;
      }
      if (j.is_discarded()) parse_json_text(content, file.string(), line);  // names the error
      throw core::InputError(file.string(), "", "not a trial record (a JSON object with trial_id)",
                             line);
    }
    check_trial_record(j, JsonPlace{file.string(), line, ""});
    const std::string id = j["trial_id"].get<std::string>();
    const auto [first, fresh] = line_of_id.emplace(id, line);
    if (fresh) {
      out.trials.push_back(std::move(j));
    } else {
      out.duplicates.push_back({line, first->second, id});
    }
    pos = eol + 1;
    out.valid_bytes = pos;
  }
  return out;
}

std::string describe_duplicates(const std::filesystem::path& file, const TrialsFile& f) {
  if (f.duplicates.empty()) return "";
  const TrialsFile::Duplicate& d = f.duplicates.front();
  std::string text = file.string() + ": " + std::to_string(f.duplicates.size()) +
                     " duplicated trial line" + (f.duplicates.size() > 1 ? "s" : "") +
                     " ignored (line " + std::to_string(d.line) + " repeats trial " + d.trial_id +
                     " of line " + std::to_string(d.first_line);
  return text + (f.duplicates.size() > 1 ? ", ...)" : ")");
}

}  // namespace taskmatrix::harness
