// Self-contained HTML reports (inline CSS and SVG, images as data URIs; no scripts, nothing
// fetched): the comparison of two runs, and the comparison of a run's planners.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare.h"

namespace taskmatrix::harness {

// A picture of a failed trial's last moment (harness/trial_video.h renders it).
struct TrialSnapshot {
  std::string run;  // "base" or "new"
  std::string trial_id, status, reason;
  std::vector<std::uint8_t> png;  // empty: no picture (the reason says why in `note`)
  std::string note;
};

// `base` and `fresh` are the runs' trials (all of them, for the distributions); `provenance`
// of each run may be null.
std::string compare_html(const Comparison& c, const std::vector<nlohmann::json>& base,
                         const std::vector<nlohmann::json>& fresh,
                         const nlohmann::json& base_provenance,
                         const nlohmann::json& new_provenance,
                         const std::vector<TrialSnapshot>& snapshots, int snapshots_left_out);

// A run with several planners: each planner against the first (`vs_reference`, one per other
// planner, base = the reference), over the run's trials.
std::string planners_html(const std::string& run_name, const std::vector<nlohmann::json>& trials,
                          const std::vector<std::string>& planners,
                          const std::vector<Comparison>& vs_reference);

// RFC 4648 base64, for data URIs.
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace taskmatrix::harness
