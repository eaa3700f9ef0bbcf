#include "harness/compare/provenance_diff.h"

#include <map>

#include "harness/results/provenance.h"

namespace taskmatrix::harness {

namespace {

std::string text_of(const nlohmann::json& j, const std::string& key) {
  if (!j.is_object()) return "";
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

// path -> entry of a model_files array; false when there is none.
bool files_of(const nlohmann::json& p, std::map<std::string, FileDifference>& out, bool base) {
  if (!p.is_object() || !p.contains("model_files") || !p["model_files"].is_array()) return false;
  for (const nlohmann::json& f : p["model_files"]) {
    if (!f.is_object()) continue;
    FileDifference& d = out[text_of(f, "path")];
    d.path = text_of(f, "path");
    d.role = text_of(f, "role");
    d.of = text_of(f, "of");
    (base ? d.base_sha256 : d.new_sha256) = text_of(f, "sha256");
  }
  return true;
}

std::string short_hash(const std::string& h) { return h.empty() ? "-" : h.substr(0, 12); }

}  // namespace

ProvenanceDiff diff_provenance(const nlohmann::json& base, const nlohmann::json& fresh) {
  ProvenanceDiff d;
  std::map<std::string, FileDifference> files;
  d.base_has_models = files_of(base, files, true);
  d.new_has_models = files_of(fresh, files, false);
  if (d.base_has_models && d.new_has_models) {
    for (const auto& [path, f] : files) {
      if (f.base_sha256.empty() || f.new_sha256.empty()) {
        d.other_models.push_back(f);
      } else if (f.base_sha256 != f.new_sha256) {
        d.changed_models.push_back(f);
      }
    }
  }
  // Scenario files, by scenario name.
  std::map<std::string, FileDifference> scenarios;
  for (const auto& [p, is_base] : {std::pair{&base, true}, std::pair{&fresh, false}}) {
    if (!p->is_object() || !p->contains("scenarios") || !(*p)["scenarios"].is_array()) continue;
    for (const nlohmann::json& s : (*p)["scenarios"]) {
      const std::string hash = text_of(s, "file_sha256");
      if (hash.empty()) continue;
      FileDifference& f = scenarios[text_of(s, "name")];
      f.of = text_of(s, "name");
      f.role = "scenario";
      f.path = text_of(s, "file");
      (is_base ? f.base_sha256 : f.new_sha256) = hash;
    }
  }
  for (const auto& [name, f] : scenarios) {
    if (!f.base_sha256.empty() && !f.new_sha256.empty() && f.base_sha256 != f.new_sha256) {
      d.changed_scenarios.push_back(f);
    }
  }
  const auto build_value = [](const nlohmann::json& p, const char* key) -> std::string {
    if (!p.is_object()) return "";
    if (std::string(key) == "build.diff_sha256") {
      return p.contains("build") ? text_of(p["build"], "diff_sha256") : "";
    }
    return text_of(p, key);
  };
  for (const auto& [key, what] : std::vector<std::pair<const char*, const char*>>{
           {"git_commit", "build commit"},
           {"git_dirty", "build had local changes"},
           {"build.diff_sha256", "local changes (SHA-256 of git diff HEAD)"},
           {"executable_sha256", "executable (SHA-256)"},
           {"mujoco_version", "MuJoCo"},
           {"ompl_version", "OMPL"}}) {
    const std::string a = build_value(base, key), b = build_value(fresh, key);
    if (a != b) d.build.push_back({what, a.empty() ? "-" : a, b.empty() ? "-" : b});
  }
  const std::optional<std::string> a = recorded_execution(base), b = recorded_execution(fresh);
  if (a && b && *a != *b) {
    d.execution = ProvenanceDiff::Value{"execution mode", execution_text(*a), execution_text(*b)};
  }
  return d;
}

nlohmann::json provenance_diff_json(const ProvenanceDiff& d) {
  const auto files = [](const std::vector<FileDifference>& list) {
    nlohmann::json a = nlohmann::json::array();
    for (const FileDifference& f : list) {
      a.push_back(
          {{"path", f.path},
           {"role", f.role},
           {"of", f.of},
           {"base_sha256",
            f.base_sha256.empty() ? nlohmann::json() : nlohmann::json(f.base_sha256)},
           {"new_sha256", f.new_sha256.empty() ? nlohmann::json() : nlohmann::json(f.new_sha256)}});
    }
    return a;
  };
  nlohmann::json build = nlohmann::json::array();
  for (const ProvenanceDiff::Value& v : d.build) {
    build.push_back({{"what", v.what}, {"base", v.base}, {"new", v.fresh}});
  }
  nlohmann::json execution = nullptr;
  if (d.execution) execution = {{"base", d.execution->base}, {"new", d.execution->fresh}};
  return {{"models_recorded", {{"base", d.base_has_models}, {"new", d.new_has_models}}},
          {"models_changed", d.models_changed()},
          {"changed_model_files", files(d.changed_models)},
          {"model_files_of_one_run", files(d.other_models)},
          {"changed_scenario_files", files(d.changed_scenarios)},
          {"build", build},
          {"execution", execution}};
}

std::string provenance_warning(const ProvenanceDiff& d) {
  std::string w;
  if (!d.base_has_models || !d.new_has_models) {
    w += std::string("WARNING: cannot tell whether the runs loaded the same model files: ") +
         (d.base_has_models  ? "the new run"
          : d.new_has_models ? "the base"
                             : "neither run") +
         " recorded their hashes (provenance.json without model_files: an older build)\n";
  }
  if (!d.changed_models.empty()) {
    w += "WARNING: the runs loaded different model files (" +
         std::to_string(d.changed_models.size()) + " changed):\n";
    for (const FileDifference& f : d.changed_models) {
      w += "  " + f.path + " (" + f.role + " of " + f.of + "): sha256 " +
           short_hash(f.base_sha256) + " -> " + short_hash(f.new_sha256) + "\n";
    }
  }
  if (d.execution) {
    w += "WARNING: the runs ran in different execution modes (base: " + d.execution->base +
         ", new: " + d.execution->fresh + "): their trials are paired all the same\n";
  }
  if (!d.changed_scenarios.empty()) {
    w += "WARNING: scenario files changed:";
    for (const FileDifference& f : d.changed_scenarios) w += " " + f.of + " (" + f.path + ")";
    w += "\n";
  }
  return w;
}

ReportTable provenance_diff_table(const ProvenanceDiff& d) {
  ReportTable t;
  t.columns = {"what", "file", "base", "new"};
  for (const FileDifference& f : d.changed_models) {
    t.rows.push_back({{"model file changed (" + f.role + " of " + f.of + ")", f.path,
                       short_hash(f.base_sha256), short_hash(f.new_sha256)},
                      "bad"});
  }
  for (const FileDifference& f : d.other_models) {
    t.rows.push_back({{"model file of one run only (" + f.role + " of " + f.of + ")", f.path,
                       short_hash(f.base_sha256), short_hash(f.new_sha256)},
                      ""});
  }
  for (const FileDifference& f : d.changed_scenarios) {
    t.rows.push_back({{"scenario file changed (" + f.of + ")", f.path, short_hash(f.base_sha256),
                       short_hash(f.new_sha256)},
                      ""});
  }
  for (const ProvenanceDiff::Value& v : d.build) {
    t.rows.push_back({{v.what, "", v.base, v.fresh}, ""});
  }
  if (d.execution) {
    t.rows.push_back({{d.execution->what, "", d.execution->base, d.execution->fresh}, "bad"});
  }
  return t;
}

}  // namespace taskmatrix::harness
