// Comparing two sets of the same trials (same scenarios, robots, environments, layouts and
// seeds): two run directories (`taskmatrix compare BASE NEW`), or two planners of one run
// (`taskmatrix run --planners A,B`). Trials are paired by their identity; per group (scenario,
// program, robot, environment, planner) and over all pairs it reports
//   - success: both rates with Wilson intervals, and McNemar's exact test on the pairs whose
//     outcome changed;
//   - planning time: the geometric mean of the per-trial ratios new/base, its 95% percentile
//     bootstrap interval and Wilcoxon's signed-rank test on the log ratios (pairs where both
//     trials planned);
//   - work counts (collision checks, plan calls, planner runs, IK calls): totals and the number
//     of trials whose count changed (these are deterministic for a given build and seed);
// and judges each as a regression or an improvement against CompareThresholds.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare/path_quality.h"
#include "harness/compare/power.h"
#include "harness/results/summary.h"

namespace taskmatrix::harness {

// When a change counts. The defaults are the README's.
struct CompareThresholds {
  double alpha = 0.05;             // significance level of McNemar's and Wilcoxon's tests
  double max_success_drop = 0.05;  // success rate drop (absolute) that, if significant, fails
  double max_time_ratio = 1.25;    // planning time: the interval's lower bound above it fails
  double max_work_ratio = 1.25;    // collision checks, new/base totals: above it fails
  int min_time_pairs = 6;          // fewer pairs that both planned: no time verdict (with 5
                                   // untied pairs Wilcoxon's p cannot go below 0.0625)
  // Trials repeat exactly on the same build (same seeds, same layouts), so a trial that now
  // fails is a change, not chance: more such pairs than this, over all groups, fail (< 0: off).
  int max_new_failures = -1;
  // Unpaired trials fail: every trial of the new run needs a partner, and so does every trial
  // of the base unless the new run is a subset of it (a fast form with fewer trials).
  bool fail_on_unpaired = false;
  bool new_is_subset = false;
  // Pairs where a clock bound decided either trial (trial_record.h, clock_bounds_hit) are not
  // reproducible: they are listed and left out of every test unless include_nonreproducible;
  // with fail_on_nonreproducible any such pair is a regression.
  bool include_nonreproducible = false;
  bool fail_on_nonreproducible = false;
  // Work counts and planned paths must repeat exactly (same build, same seeds: they do, under
  // any load): a pair whose counts or path digests differ is a regression.
  bool exact_work = false;
  // Not thresholds: the changes the power section says how many trials would detect (a drop
  // of success_target points; a planning-time ratio of time_target, 0: max_time_ratio).
  double power_success_target = 0.10;
  double power_time_target = 0;
};

// What the new run's planners were given, for telling a planner that spends its time budget
// by design from a slower one: the OMPL names of the planners that optimize until their time
// limit (harness/compare/planner_comparison.h finds them), and the time limit of a plan call per
// scenario (absent: not recorded).
struct PlannerBudgets {
  std::set<std::string> anytime_planners;
  std::map<std::string, double> plan_time_limit_s;
};

struct WorkCountChange {
  std::string field;                     // an exact work count of harness/results/trial_schema.h
  double base_total = 0, new_total = 0;  // over pairs where both trials have the count
  int changed_trials = 0;                // pairs whose counts differ
  int missing = 0;  // pairs where either lacks it (null: a crash or kill), left out of totals
  int missing_in_successful_new = 0;  // new trials that succeeded without it: a broken writer
};

struct PairedGroup {
  std::string scenario, program, robot, environment;
  std::string base_planner, new_planner;  // equal when comparing runs
  int pairs = 0;
  int base_successes = 0, new_successes = 0;
  Interval base_ci, new_ci;
  int only_base_success = 0, only_new_success = 0;  // discordant pairs
  double mcnemar_p = 1;
  // Planning time, over pairs where both trials planned (planning_time_s > 0).
  int time_pairs = 0;
  double time_ratio = NAN, time_ratio_low = NAN, time_ratio_high = NAN;
  double wilcoxon_p = NAN;
  std::vector<double> base_planning_s, new_planning_s;  // paired, for plots
  std::vector<std::string> time_pair_ids;               // the new trial of each such pair
  std::vector<WorkCountChange> work;
  // Pairs whose plans' path digests were both recorded, and of those the ones that differ.
  int path_pairs = 0, changed_paths = 0;
  // Verdicts against the thresholds, e.g. "success 100% -> 67% (McNemar p = 0.031)".
  std::vector<std::string> regressions, improvements;
  // Changes that would be regressions but are by design: more planning time and checks by a
  // planner that optimizes until its time limit and stayed within it (with no more plan
  // calls than the base; a call that runs the planner for several goal poses has the limit
  // for each).
  std::vector<std::string> by_design;
  // Path quality over the pairs where both succeeded (harness/compare/path_quality.h); significant
  // changes as phrases (reported, not judged).
  std::vector<PathQualityChange> path_quality;
  std::vector<std::string> path_findings;
  // How small a change this group could have detected (harness/compare/power.h).
  GroupPower power;
  // Failed trials by where and why (failure_location: reason), per run.
  std::map<std::string, int> base_failures, new_failures;
};

struct Comparison {
  std::string base_label, new_label;  // run directories or planner labels
  CompareThresholds thresholds;
  std::vector<PairedGroup> groups;  // sorted by scenario, program, robot, environment, planner
  PairedGroup overall;              // every pair pooled
  std::vector<std::string> only_in_base, only_in_new;  // trial ids without a partner
  // Ids of pairs whose success changed, with both statuses.
  struct Flip {
    std::string base_id, new_id, base_status, new_status;
    bool now_succeeds = false;
    // The failing trial's failure_location (where in its programs it failed) and reason.
    std::string where, reason;
  };
  std::vector<Flip> flips;
  // Pairs left out because a clock bound decided a trial: "base id / new id: what".
  std::vector<std::string> nonreproducible;
  bool regression() const;
};

// The identity of a trial for pairing: every field of its id, with or without the planner.
std::string pairing_key(const nlohmann::json& trial, bool with_planner);

// Pairs `base` and `fresh` trials by pairing_key(trial, with_planner) and compares them.
// Trials whose key appears twice on one side throw std::invalid_argument.
// `budgets`: what the new run's planners were given (empty: no change is by design).
Comparison compare_trials(const std::vector<nlohmann::json>& base,
                          const std::vector<nlohmann::json>& fresh, bool with_planner,
                          const CompareThresholds& thresholds, const PlannerBudgets& budgets = {});

// Where in its programs a failed trial failed, e.g. "pickup > grasp": the path its failure
// reason names ("tidy > greet > postural(rest): invalid_goal: ..."), else the programs whose
// failed events carry the first failure's reason, outermost first; "" when no program failed
// (a crash, a timeout, a success criterion that does not hold).
std::string failure_location(const nlohmann::json& trial);

nlohmann::json comparison_json(const Comparison& c);

// A p-value for reports as "0.012" or "<0.001"; and as a phrase after "p ": "= 0.012" or
// "< 0.001".
std::string p_value_text(double p);
std::string p_value_phrase(double p);
// "1 trial changed", "3 trials changed".
std::string trials_changed(double n);
std::string comparison_markdown(const Comparison& c);

// How a by-design change is introduced in verdicts.
inline constexpr const char* kByDesign = "slower, within budget by design";
// The verdict of a group without a significant change: "no significant change", and when the
// group could not have detected a success drop of t.max_success_drop, that it was underpowered
// and what it could have detected.
std::string no_change_text(const PairedGroup& g, const CompareThresholds& t);

}  // namespace taskmatrix::harness
