// The trial record's fields in one table: what each holds and in which unit, whether it is a
// timing (depends on the machine and its load), how summary.json summarises it, whether it is
// a property of the Planner Arena log (ompl.log) and of which type there, whether it is an
// exact work count (repeats exactly for the same trial id; `compare --exact-work` requires it),
// and how the reports show it (FieldDisplay). trial_record.cc (the fields a trial without a
// result nulls), summary.cc (summary.json and summary.md's columns), ompl_log.cc, compare.cc
// (the work counts, and the per-group columns of compare's tables), path_quality.cc (the
// measures compared) and planner_comparison.cc and html_report.cc (the planners' tables) take
// their field lists from here; the table in docs/architecture.md is checked against it by a
// test.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace taskmatrix::harness {

// Who writes a field: the trial's identity (from the trial matrix), its outcome, a worker's
// measurement (null when the worker produced no result: a crash, a kill), or the runner.
enum class FieldSource { kIdentity, kOutcome, kMeasured, kRunner };

// summary.json's statistic of a field per group: none, the median, or median, p90 and n.
enum class FieldSummary { kNone, kMedian, kMedianP90 };

// A Planner Arena property's type in ompl.log (kNone: not a property).
enum class OmplType { kNone, kReal, kInteger, kBoolean, kEnum };

// Which way a path-quality measure is better (kNone: not a path-quality measure).
enum class Better { kNone, kLower, kHigher };

// How the reports show a field; a field no report shows leaves it empty.
struct FieldDisplay {
  std::string_view label = {};       // its name in reports: "end-effector path"
  std::string_view unit = {};        // printed after its values in reports: "m"; "" for none
  std::string_view format = {};      // printf format of a value in a table column: "%.2f"
  std::string_view summary_md = {};  // its column heading in summary.md ("" when not shown there):
                                     // the group's median, and the p90 where summary.json has one
  bool compare_groups = false;       // a column of compare's per-group tables (totals base -> new);
                                     // an exact work count
  bool planner_table = false;        // a column of the planners' tables: the median per planner
  Better path_quality = Better::kNone;  // a path-quality measure of compare: which way is better
  std::string_view better_word = {}, worse_word = {};  // for its findings: "shorter", "longer"
};

struct TrialField {
  std::string_view name;
  std::string_view unit;  // "s", "m", "rad or m", "count", ...; "" for text and structures
  FieldSource source;
  bool timing;  // measured on the clock: varies with the machine and its load
  FieldSummary summary;
  std::string_view ompl_property;  // its name in ompl.log; "" when not a property
  OmplType ompl_type;
  bool exact_work;  // an exact work count, which depends on the trial id alone
  std::string_view doc;
  FieldDisplay display = {};
};

// The table, in the order ompl.log lists its properties and compare its work counts.
inline constexpr std::array kTrialFields = {
    TrialField{"trial_id", "", FieldSource::kIdentity, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "scenario.robot.environment.planner.l(layout seed).s(seed)"},
    TrialField{"scenario", "", FieldSource::kIdentity, false, FieldSummary::kNone, "scenario",
               OmplType::kEnum, false, "the scenario's name"},
    TrialField{"robot", "", FieldSource::kIdentity, false, FieldSummary::kNone, "robot",
               OmplType::kEnum, false, "the robot's name"},
    TrialField{"environment", "", FieldSource::kIdentity, false, FieldSummary::kNone, "environment",
               OmplType::kEnum, false, "the environment's name"},
    TrialField{"program", "", FieldSource::kIdentity, false, FieldSummary::kNone, "program",
               OmplType::kEnum, false, "the scenario's program"},
    TrialField{"planner", "", FieldSource::kIdentity, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "the planner's label in the scenario"},
    TrialField{"planner_name", "", FieldSource::kIdentity, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "the registered planner it runs"},
    TrialField{"execution", "", FieldSource::kIdentity, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "physics, kinematic or physics_unpruned"},
    TrialField{"seed", "", FieldSource::kIdentity, false, FieldSummary::kNone, "seed",
               OmplType::kInteger, false, "the programs' seed"},
    TrialField{"layout_seed", "", FieldSource::kIdentity, false, FieldSummary::kNone, "layout seed",
               OmplType::kInteger, false, "the seed of the drawn world"},
    TrialField{"success", "", FieldSource::kOutcome, false, FieldSummary::kNone, "solved",
               OmplType::kBoolean, false, "set-up, program and success condition all held"},
    TrialField{"status", "", FieldSource::kOutcome, false, FieldSummary::kNone, "trial status",
               OmplType::kEnum, false, "success, or the failure's code"},
    TrialField{"failure_reason", "", FieldSource::kOutcome, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "the failure as a user reads it (600 characters at most)"},
    TrialField{
        "planning_time_s",
        "s",
        FieldSource::kMeasured,
        true,
        FieldSummary::kMedianP90,
        "time",
        OmplType::kReal,
        false,
        "planners' solve time, over the plan calls",
        {.label = "planning time", .unit = "s", .format = "%.3f", .summary_md = "planning s"}},
    TrialField{"simplification_time_s", "s", FieldSource::kMeasured, true, FieldSummary::kMedian,
               "simplification time", OmplType::kReal, false, "path simplification time"},
    TrialField{"collision_checks",
               "count",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "collision checks",
               OmplType::kInteger,
               true,
               "the planners' validity checks, the certification of the paths they return, and "
               "is_valid queries",
               {.label = "collision checks",
                .format = "%.0f",
                .compare_groups = true,
                .planner_table = true}},
    TrialField{"plan_calls",
               "count",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "plan calls",
               OmplType::kInteger,
               true,
               "the programs' plan requests",
               {.label = "plan calls", .format = "%.0f", .compare_groups = true}},
    TrialField{"planner_runs", "count", FieldSource::kMeasured, false, FieldSummary::kNone, "",
               OmplType::kNone, true,
               "planner runs behind the plan calls (one per pose tried; two where a path touched "
               "something between checked states and was planned again)"},
    TrialField{"ik_calls", "count", FieldSource::kMeasured, false, FieldSummary::kNone, "",
               OmplType::kNone, true, "inverse kinematics solves"},
    TrialField{"ik_time_s", "s", FieldSource::kMeasured, true, FieldSummary::kNone, "ik time",
               OmplType::kReal, false, "inverse kinematics time, pose goals of plans included"},
    TrialField{"path_length_joint",
               "rad or m",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "path length joint",
               OmplType::kReal,
               false,
               "the executed path of all joints",
               {.label = "joint path",
                .format = "%.2f",
                .summary_md = "joint path",
                .planner_table = true,
                .path_quality = Better::kLower,
                .better_word = "shorter",
                .worse_word = "longer"}},
    TrialField{"path_length_ee_m",
               "m",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "path length ee",
               OmplType::kReal,
               false,
               "the executed path of the end effectors",
               {.label = "end-effector path",
                .unit = "m",
                .format = "%.2f",
                .summary_md = "EE path m",
                .path_quality = Better::kLower,
                .better_word = "shorter",
                .worse_word = "longer"}},
    TrialField{"duration_s",
               "s (simulated)",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "duration",
               OmplType::kReal,
               false,
               "the program's simulated time, set-up excluded",
               {.label = "duration",
                .unit = "s",
                .format = "%.1f",
                .summary_md = "duration s",
                .path_quality = Better::kLower,
                .better_word = "shorter",
                .worse_word = "longer"}},
    TrialField{"sim_time_s", "s (simulated)", FieldSource::kMeasured, false, FieldSummary::kNone,
               "", OmplType::kNone, false, "the whole trial's simulated time"},
    TrialField{"smoothness",
               "rad/s^3",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "smoothness",
               OmplType::kReal,
               false,
               "RMS joint jerk of the executed motion",
               {.label = "smoothness (RMS jerk)",
                .unit = "rad/s^3",
                .path_quality = Better::kLower,
                .better_word = "smoother",
                .worse_word = "jerkier"}},
    TrialField{"min_clearance_m",
               "m",
               FieldSource::kMeasured,
               false,
               FieldSummary::kMedian,
               "min clearance",
               OmplType::kReal,
               false,
               "smallest distance of the moving chains to anything",
               {.label = "minimum clearance",
                .unit = "m",
                .path_quality = Better::kHigher,
                .better_word = "wider",
                .worse_word = "narrower"}},
    TrialField{"clearance_samples", "count", FieldSource::kMeasured, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "states whose clearance was measured"},
    TrialField{"control_periods", "count", FieldSource::kMeasured, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "control periods simulated"},
    TrialField{"trial_wall_s", "s", FieldSource::kMeasured, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "wall clock inside the trial"},
    TrialField{"executive_wall_s", "s", FieldSource::kMeasured, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "wall clock inside the executive"},
    TrialField{"stepping_wall_s", "s", FieldSource::kMeasured, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "wall clock stepping the simulation"},
    TrialField{"monitoring_wall_s", "s", FieldSource::kMeasured, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "wall clock monitoring execution (collisions, clearance)"},
    TrialField{"contacts_per_pass", "contacts", FieldSource::kMeasured, false, FieldSummary::kNone,
               "", OmplType::kNone, false, "contacts per collision pass of execution"},
    TrialField{"events", "", FieldSource::kOutcome, false, FieldSummary::kNone, "", OmplType::kNone,
               false, "the programs' messages with simulated times"},
    TrialField{"layout", "", FieldSource::kOutcome, false, FieldSummary::kNone, "", OmplType::kNone,
               false, "the drawn world: task variation and obstacles"},
    TrialField{"plans", "", FieldSource::kOutcome, false, FieldSummary::kNone, "", OmplType::kNone,
               false, "per plan call: status, times, counts, path digest"},
    TrialField{"clock_bound_hit", "", FieldSource::kOutcome, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "the clock bounds that decided the trial"},
    TrialField{"removed_debris", "", FieldSource::kOutcome, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "debris a tool removed"},
    TrialField{"trajectory", "", FieldSource::kRunner, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "the recorded states' file, relative to the run"},
    TrialField{"trajectory_frames", "count", FieldSource::kRunner, false, FieldSummary::kNone, "",
               OmplType::kNone, false, "frames in it"},
    TrialField{"wall_time_s", "s", FieldSource::kRunner, true, FieldSummary::kMedian, "wall time",
               OmplType::kReal, false, "the worker's wall clock, fork to reaped"},
    TrialField{"peak_memory_mb", "MB", FieldSource::kRunner, true, FieldSummary::kMedian, "memory",
               OmplType::kReal, false, "the worker's peak resident memory"},
    TrialField{"cpu_time_s", "s", FieldSource::kRunner, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "the worker's user and system CPU time"},
    TrialField{"overhead_s", "s", FieldSource::kRunner, true, FieldSummary::kNone, "",
               OmplType::kNone, false, "wall_time_s minus executive_wall_s"},
};

// Whether the table has a field of this name.
constexpr bool has_trial_field(std::string_view name) {
  for (const TrialField& f : kTrialFields) {
    if (f.name == name) return true;
  }
  return false;
}

// The fields reports single out by name: the time the paired verdicts compare (compare's
// planning-time ratio, the planners' median time column and the plan-time budget) and the work
// count the planners' verdicts quote as a ratio. Checked against the table when compiled.
inline constexpr const char* kPlanningTimeField = "planning_time_s";
inline constexpr const char* kCollisionChecksField = "collision_checks";
static_assert(has_trial_field(kPlanningTimeField) && has_trial_field(kCollisionChecksField));

// The timings (fields measured on the clock), in table order: what compare and the
// reproducibility checks leave out.
const std::vector<std::string>& timing_fields();

// The exact work counts (compare's --exact-work fields), in table order.
std::vector<std::string> exact_work_fields();
// "REAL", "INTEGER", "BOOLEAN", "ENUM".
const char* to_string(OmplType type);
// The table as docs/architecture.md holds it (Markdown).
std::string trial_fields_markdown();

}  // namespace taskmatrix::harness
