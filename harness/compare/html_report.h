// Self-contained HTML reports (inline CSS and SVG, images as data URIs; no scripts, nothing
// fetched): the comparison of two runs, and the comparison of a run's planners.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare/compare.h"
#include "harness/compare/provenance_diff.h"
#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

// Pictures of a failed trial at the moment it failed (harness/replay/trial_video.h renders them).
struct TrialSnapshot {
  std::string run;  // "base" or "new"
  std::string trial_id, status, reason;
  std::string where;                   // failure_location (harness/compare/compare.h)
  std::vector<std::uint8_t> png;       // the overview; empty: no picture (`note` says why)
  std::vector<std::uint8_t> close_up;  // aimed at the moving hand or held object
  double time_s = -1;                  // simulated time shown
  std::string focus;                   // what the close-up looks at
  std::vector<std::string> commands;   // shell commands that render the trial's videos
  std::string note;
};

// `base` and `fresh` are the runs' trials (all of them, for the distributions); `provenance`
// of each run may be null; `differences` (may be null) what differs between them.
std::string compare_html(const Comparison& c, const std::vector<nlohmann::json>& base,
                         const std::vector<nlohmann::json>& fresh,
                         const nlohmann::json& base_provenance,
                         const nlohmann::json& new_provenance,
                         const std::vector<TrialSnapshot>& snapshots, int snapshots_left_out,
                         const ProvenanceDiff* differences = nullptr);

// A run with several planners: each planner against the first (`vs_reference`, one per other
// planner, base = the reference), over the run's trials. The summary per planner shows the
// measures of `fields` marked for the planners' tables (FieldDisplay::planner_table).
std::string planners_html(const std::string& run_name, const std::vector<nlohmann::json>& trials,
                          const std::vector<std::string>& planners,
                          const std::vector<Comparison>& vs_reference,
                          std::span<const TrialField> fields = kTrialFields);

// RFC 4648 base64, for data URIs.
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace taskmatrix::harness
