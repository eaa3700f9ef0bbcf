// What differs between the provenance of two runs (harness/results/provenance.h), for `compare`:
// the model, profile and environment files whose SHA-256 changed (matched by their path relative to
// each run's root), files only one run loaded, scenario files that changed, and the build
// (commit, local changes, executable, MuJoCo and OMPL versions).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/report/report_table.h"

namespace taskmatrix::harness {

struct FileDifference {
  std::string path, role, of;           // of: the robot, environment or scenario
  std::string base_sha256, new_sha256;  // "" where the run did not load it
};

struct ProvenanceDiff {
  // False when a run's provenance.json is missing or has no model_files (an older build):
  // then nothing can be said about its models.
  bool base_has_models = false, new_has_models = false;
  std::vector<FileDifference> changed_models;  // loaded by both, different bytes
  std::vector<FileDifference> other_models;    // loaded by one run only
  std::vector<FileDifference> changed_scenarios;
  struct Value {
    std::string what, base, fresh;
  };
  std::vector<Value> build;  // build and library differences
  // The runs' --execution overrides (matrix.overrides.execution), where they differ and both
  // recorded one: trials are paired by id, which does not name the execution mode.
  std::optional<Value> execution;

  // What --fail-on-model-change fails on: a changed model file, or models not recorded.
  bool models_changed() const {
    return !changed_models.empty() || !base_has_models || !new_has_models;
  }
};

// `base` and `fresh` may be null (no provenance.json).
ProvenanceDiff diff_provenance(const nlohmann::json& base, const nlohmann::json& fresh);

nlohmann::json provenance_diff_json(const ProvenanceDiff& d);
// Warning lines for the console and reports ("" when the runs loaded the same models and the
// same build ran): "WARNING: the runs loaded different model files: ...".
std::string provenance_warning(const ProvenanceDiff& d);
// Every difference: what, path, base, new.
ReportTable provenance_diff_table(const ProvenanceDiff& d);

}  // namespace taskmatrix::harness
