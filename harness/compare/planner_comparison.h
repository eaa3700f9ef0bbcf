// A run with several planners (`taskmatrix run ... --planners RRTConnect,BITstar,PRM`) runs
// the same trials under each; this compares every planner with the first, pair by pair
// (harness/compare/compare.h): planners.md, planners.html and a section of summary.md.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare/compare.h"
#include "harness/results/trial_schema.h"
#include "harness/scenario/scenario.h"

namespace taskmatrix::harness {

// What the planners of a run were given (harness/compare/compare.h): from its scenarios, or from
// its provenance.json (scenarios[].planners[].name and plan_time_limit_s; a provenance without
// plan_time_limit_s leaves the limits unknown).
PlannerBudgets planner_budgets(const RunPlan& plan);
PlannerBudgets planner_budgets(const nlohmann::json& provenance);

// Each planner after the first against the first, on the trials of both. Empty for fewer
// than two planners with trials.
std::vector<Comparison> compare_planners(const std::vector<nlohmann::json>& trials,
                                         const std::vector<std::string>& planners,
                                         const PlannerBudgets& budgets = {});

// The measures of the planners' tables (planners.html and the table below): the rows of
// `fields` with FieldDisplay::planner_table, in table order. Their headings, "joint path
// (median)", and one planner's cells: the median of each over its trials in `trials`, in the
// field's format ("-" where none has it).
std::vector<std::string> planner_measure_headings(
    std::span<const TrialField> fields = kTrialFields);
std::vector<std::string> planner_measure_cells(const std::vector<nlohmann::json>& trials,
                                               const std::string& planner,
                                               std::span<const TrialField> fields = kTrialFields);

// The table for summary.md: one row per planner (success with interval, median planning
// time, the planner table's measures, and against the reference: McNemar p, planning-time
// ratio with interval, collision checks ratio, verdicts).
std::string planner_table_markdown(const std::vector<nlohmann::json>& trials,
                                   const std::vector<std::string>& planners,
                                   const std::vector<Comparison>& vs_reference,
                                   std::span<const TrialField> fields = kTrialFields);

// Writes planners.md (the table and each comparison in full) and planners.html into `dir`.
void write_planner_comparison(const std::filesystem::path& dir, const std::string& run_name,
                              const std::vector<nlohmann::json>& trials,
                              const std::vector<std::string>& planners,
                              const std::vector<Comparison>& vs_reference);

}  // namespace taskmatrix::harness
