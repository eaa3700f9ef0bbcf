#include "harness/results/ompl_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "harness/results/provenance.h"
#include "harness/results/summary.h"
#include "harness/results/trial_schema.h"
#include "taskmatrix/core/failure.h"

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

std::string ompl_log_text(const OmplLogInfo& info, std::vector<nlohmann::json> trials,
                          std::span<const TrialField> fields) {
  std::sort(trials.begin(), trials.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.value("trial_id", std::string()) < b.value("trial_id", std::string());
  });
  // Enumerations over what the trials hold, one per ENUM property, named after it ("trial
  // status": "trial_status", apart from OMPL's own planner "status" enum, which a database may
  // already hold).
  std::vector<Enum> enums;
  std::vector<std::string> enum_keys;  // the trial field of each
  for (const TrialField& f : fields) {
    if (f.ompl_type != OmplType::kEnum) continue;
    std::string name(f.ompl_property);
    std::replace(name.begin(), name.end(), ' ', '_');
    enums.push_back({name, {}});
    enum_keys.emplace_back(f.name);
  }
  for (const nlohmann::json& t : trials) {
    for (size_t k = 0; k < enums.size(); ++k) {
      std::vector<std::string>& values = enums[k].values;
      const std::string v = one_token(t.value(enum_keys[k], std::string("unknown")));
      if (std::find(values.begin(), values.end(), v) == values.end()) values.push_back(v);
    }
  }
  for (Enum& e : enums) std::sort(e.values.begin(), e.values.end());
  // Trial statuses start with a fixed list, "success" and every failure code in the order of
  // core::FailureCode (new codes are added at its end), so that logs of different runs agree on
  // the indices of every status they share with it (a database keeps the first log's enum).
  for (size_t k = 0; k < enums.size(); ++k) {
    if (enum_keys[k] != "status") continue;
    std::vector<std::string> statuses = {"success"};
    for (core::FailureCode code : core::all_failure_codes()) {
      statuses.push_back(core::to_string(code));
    }
    for (const std::string& v : enums[k].values) {
      if (std::find(statuses.begin(), statuses.end(), v) == statuses.end()) statuses.push_back(v);
    }
    enums[k].values = statuses;
  }
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
  std::vector<TrialField> properties;
  for (const TrialField& f : fields) {
    if (f.ompl_type != OmplType::kNone) properties.push_back(f);
  }
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
    for (const TrialField& f : properties) {
      out += std::string(f.ompl_property) + " " + to_string(f.ompl_type) + "\n";
    }
    const auto& list = by_planner.at(p->label);
    out += std::to_string(list.size()) + " runs\n";
    for (const nlohmann::json* t : list) {
      for (const TrialField& f : properties) {
        const std::string key(f.name);
        const nlohmann::json& v = t->contains(key) ? (*t)[key] : nlohmann::json(nullptr);
        if (f.ompl_type == OmplType::kEnum) {
          const size_t e = static_cast<size_t>(std::find(enum_keys.begin(), enum_keys.end(), key) -
                                               enum_keys.begin());
          const std::string value = one_token(v.is_string() ? v.get<std::string>() : "unknown");
          out += std::to_string(enums[e].index(value));
        } else if (f.ompl_type == OmplType::kBoolean) {
          out += v.is_boolean() && v.get<bool>() ? "1" : "0";
        } else if (f.ompl_type == OmplType::kInteger) {
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
