// provenance.json: what produced a run, so that two runs can be compared honestly: the git
// commit (and whether the tree had changes), MuJoCo and OMPL versions, compiler, host (name,
// CPU model, cores, memory), the SHA-256 of the scenario files, seeds and overrides, the
// command line, and when it ran; the matrix it ran (the suite file's absolute path, the
// overrides, the trial count) and, in a Slurm job, the job's ids; the SHA-256 of the
// executable that ran the trials (what `merge` checks as the same build).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/scenario.h"

namespace taskmatrix::harness {

// SHA-256 (hex) of the run plan's files: the suite file and every scenario file, each as
// its path relative to the plan's folder and its bytes.
std::string plan_hash(const RunPlan& plan);

std::string host_name();
std::string cpu_model();  // /proc/cpuinfo's model name
std::string utc_now_iso();
// From OMPL's version macros (Debian's OMPL_VERSION string is empty), e.g. "1.5.2".
std::string ompl_version();
std::string mujoco_version();  // e.g. "2.2.2"
// SHA-256 (hex) of the running executable (/proc/self/exe); "unknown" if unreadable.
std::string executable_hash();

nlohmann::json make_provenance(const RunPlan& plan, const std::filesystem::path& repo_root,
                               const std::vector<std::string>& command_line, int jobs);

// What defines a run's trial matrix: {"file": the suite or scenario file's absolute path,
// "trials": trials of the whole matrix, "overrides": {"trials", "seed", "planners"}} (null
// or empty where not overridden). load_run_plan(file) + apply_overrides(overrides_of(...))
// gives the same matrix again.
nlohmann::json matrix_provenance(const RunPlan& plan, const RunOverrides& overrides, size_t trials);
// The overrides of a matrix_provenance() object. Throws core::InputError naming `file`.
RunOverrides overrides_of(const nlohmann::json& matrix, const std::string& file);
// The Slurm job a process runs in: job_id, array_job_id, array_task_id, cluster, partition and
// nodes, from SLURM_* variables; an empty object outside Slurm.
nlohmann::json slurm_provenance();

}  // namespace taskmatrix::harness
