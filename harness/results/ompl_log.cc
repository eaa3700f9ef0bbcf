#include "harness/results/ompl_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "harness/results/provenance.h"
#include "harness/results/summary.h"

namespace taskmatrix::harness {

namespace {

// A name as one token of the log: UTF-8 (Python reads the log as text), no spaces, control
// characters or the log's separators.
std::string one_token(const std::string& text) {
  std::string s = valid_utf8(text);
  for (char& c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u == 0x7f || c == ';' || c == '|') c = '_';
  }
  return s.empty() ? "unnamed" : s;
}

std::string real(const nlohmann::json& v) {
  if (!v.is_number()) return "nan";
  const double d = v.get<double>();
  if (!std::isfinite(d)) return "nan";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", d);
  return buf;
}

std::string integer(const nlohmann::json& v) {
  if (!v.is_number()) return "nan";
  return std::to_string(static_cast<long long>(v.get<double>()));
}

// Multi-line values may not contain the closing marker, a carriage return (Python's readline
// ends a line there) or text that is not UTF-8.
std::string block(const std::string& raw) {
  std::string text;
  const std::string utf8 = valid_utf8(raw);
  for (size_t i = 0; i < utf8.size(); ++i) {
    if (utf8[i] != '\r') {
      text += utf8[i];
    } else if (i + 1 >= utf8.size() || utf8[i + 1] != '\n') {
      text += '\n';
    }
  }
  std::string out;
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t eol = text.find('\n', pos);
    std::string line = text.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos);
    if (line.rfind("|>>>", 0) == 0) line = " " + line;
    out += line + "\n";
    if (eol == std::string::npos) break;
    pos = eol + 1;
  }
  return out;
}

struct Enum {
  std::string name;
  std::vector<std::string> values;
  int index(const std::string& v) const {
    return static_cast<int>(std::find(values.begin(), values.end(), v) - values.begin());
  }
};

}  // namespace

std::string ompl_log_text(const OmplLogInfo& info, std::vector<nlohmann::json> trials) {
  std::sort(trials.begin(), trials.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.value("trial_id", std::string()) < b.value("trial_id", std::string());
  });
  // Enumerations over what the trials hold. The trial status is named apart from OMPL's own
  // planner "status" enum, which a database may already hold.
  std::vector<Enum> enums = {
      {"trial_status", {}}, {"scenario", {}}, {"program", {}}, {"robot", {}}, {"environment", {}}};
  for (const nlohmann::json& t : trials) {
    for (Enum& e : enums) {
      const std::string key = e.name == "trial_status" ? "status" : e.name;
      const std::string v = one_token(t.value(key, std::string("unknown")));
      if (std::find(e.values.begin(), e.values.end(), v) == e.values.end()) e.values.push_back(v);
    }
  }
  for (Enum& e : enums) std::sort(e.values.begin(), e.values.end());
  // Trial statuses start with a fixed list, so that logs of different runs agree on the
  // indices of every status they share with it (a database keeps the first log's enum).
  static const std::vector<std::string> kKnownStatuses = {"success",
                                                          "crash",
                                                          "timeout",
                                                          "sim_unstable",
                                                          "setup_failed",
                                                          "time_limit",
                                                          "criterion_false",
                                                          "planning_timeout",
                                                          "ik_failure",
                                                          "collision",
                                                          "grasp_failed",
                                                          "invalid_start",
                                                          "invalid_goal",
                                                          "invalid_input",
                                                          "precondition_false",
                                                          "invariant_false",
                                                          "no_transition",
                                                          "perception_miss",
                                                          "not_graspable",
                                                          "coverage_short",
                                                          "chains_busy",
                                                          "approximate_solution"};
  std::vector<std::string> statuses = kKnownStatuses;
  for (const std::string& v : enums[0].values) {
    if (std::find(statuses.begin(), statuses.end(), v) == statuses.end()) statuses.push_back(v);
  }
  enums[0].values = statuses;
  std::map<std::string, std::vector<const nlohmann::json*>> by_planner;
  for (const nlohmann::json& t : trials) by_planner[t.value("planner", "")].push_back(&t);

  std::string out;
  out += "OMPL version " + ompl_version() + "\n";
  out += "Experiment " + one_token(info.experiment) + "\n";
  out += "Running on " + one_token(info.hostname) + "\n";
  out += "Starting at " + one_token(info.date) + "\n";
  out += "<<<|\n" + block(info.setup) + "|>>>\n";
  out += "<<<|\n" + block(info.cpuinfo) + "|>>>\n";
  out += std::to_string(info.seed) + " is the random seed\n";
  out += real(info.time_limit_s) + " seconds per run\n";
  out += "0 MB per run\n";
  size_t per_planner = 0;
  for (const auto& [label, list] : by_planner) per_planner = std::max(per_planner, list.size());
  out += std::to_string(per_planner) + " runs per planner\n";
  out += real(info.total_time_s) + " seconds spent to collect the data\n";
  out += std::to_string(enums.size()) + " enum types\n";
  for (const Enum& e : enums) {
    out += e.name;
    for (const std::string& v : e.values) out += "|" + v;
    out += "\n";
  }
  static const std::vector<std::pair<const char*, const char*>> properties = {
      {"time REAL", "planning_time_s"},
      {"simplification time REAL", "simplification_time_s"},
      {"solved BOOLEAN", "success"},
      {"trial status ENUM", "status"},
      {"scenario ENUM", "scenario"},
      {"program ENUM", "program"},
      {"robot ENUM", "robot"},
      {"environment ENUM", "environment"},
      {"layout seed INTEGER", "layout_seed"},
      {"seed INTEGER", "seed"},
      {"plan calls INTEGER", "plan_calls"},
      {"collision checks INTEGER", "collision_checks"},
      {"ik time REAL", "ik_time_s"},
      {"path length joint REAL", "path_length_joint"},
      {"path length ee REAL", "path_length_ee_m"},
      {"duration REAL", "duration_s"},
      {"smoothness REAL", "smoothness"},
      {"min clearance REAL", "min_clearance_m"},
      {"wall time REAL", "wall_time_s"},
      {"memory REAL", "peak_memory_mb"},
  };
  std::vector<const OmplLogInfo::Planner*> planners;
  for (const OmplLogInfo::Planner& p : info.planners) {
    if (by_planner.count(p.label)) planners.push_back(&p);
  }
  out += std::to_string(planners.size()) + " planners\n";
  for (const OmplLogInfo::Planner* p : planners) {
    out += "geometric_" + one_token(p->label) + "\n";
    out += std::to_string(p->params.size() + 1) + " common properties\n";
    out += "planner STRING = " + one_token(p->name) + "\n";
    for (const auto& [k, v] : p->params) out += one_token(k) + " STRING = " + one_token(v) + "\n";
    out += std::to_string(properties.size()) + " properties for each run\n";
    for (const auto& [decl, key] : properties) out += std::string(decl) + "\n";
    const auto& list = by_planner.at(p->label);
    out += std::to_string(list.size()) + " runs\n";
    for (const nlohmann::json* t : list) {
      for (const auto& [decl, key] : properties) {
        const std::string d(decl);
        const nlohmann::json& v = t->contains(key) ? (*t)[key] : nlohmann::json(nullptr);
        if (d.find(" ENUM") != std::string::npos) {
          const std::string enum_name = std::string(key) == "status" ? "trial_status" : key;
          const Enum& e = *std::find_if(enums.begin(), enums.end(),
                                        [&](const Enum& x) { return x.name == enum_name; });
          out +=
              std::to_string(e.index(one_token(v.is_string() ? v.get<std::string>() : "unknown")));
        } else if (d.find(" BOOLEAN") != std::string::npos) {
          out += v.is_boolean() && v.get<bool>() ? "1" : "0";
        } else if (d.find(" INTEGER") != std::string::npos) {
          out += integer(v);
        } else {
          out += real(v);
        }
        out += "; ";
      }
      out += "\n";
    }
    out += ".\n";
  }
  return out;
}

}  // namespace taskmatrix::harness
