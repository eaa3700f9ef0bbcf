// provenance.json: what produced a run, so that two runs can be compared honestly: the build
// (the git commit the binary was built from, whether that tree had changes and a hash of
// them, embedded at build time: harness/results/build_info.h), the checkout the models were read
// from (TASKMATRIX_ROOT; its commit, or that it is not a git checkout), the SHA-256 of every model,
// profile and environment file the run loaded, MuJoCo and OMPL versions, compiler, host (name,
// CPU model, cores, memory), the SHA-256 of the scenario files, seeds and overrides, the
// command line, and when it ran; the matrix it ran (the suite file's absolute path, the
// overrides, the trial count) and, in a Slurm job, the job's ids; the SHA-256 of the
// executable that ran the trials (what `merge` checks as the same build).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/scenario/scenario.h"
#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/robot_profile.h"

namespace taskmatrix::harness {

// SHA-256 (hex) of the run plan's files: the suite file and every scenario file, each as
// its path relative to the plan's folder and its bytes.
std::string plan_hash(const RunPlan& plan);

std::string host_name();
std::string cpu_model();  // /proc/cpuinfo's model name
std::string utc_now_iso();
// From OMPL's version macros (Debian's OMPL_VERSION string is empty), e.g. "1.5.2".
std::string ompl_version();
// SHA-256 (hex) of the running executable (/proc/self/exe); "unknown" if unreadable.
std::string executable_hash();

// SHA-256 (hex) of a file's bytes; "" when it cannot be read.
std::string file_sha256(const std::filesystem::path& file);

// `repo_root` is the catalog root (TASKMATRIX_ROOT): recorded with its own git state under
// "root"; "git_commit" and "git_dirty" are the build's (what ran); `mujoco_version` is the
// backend's (harness/run/run_job.h).
nlohmann::json make_provenance(const RunPlan& plan, const std::filesystem::path& repo_root,
                               const std::vector<std::string>& command_line, int jobs,
                               const std::string& mujoco_version);

// The model files the scenes loaded: for each robot its profile and model (MJCF or URDF), for
// each environment its spec and model, and the files those models reference (MJCF <include>,
// meshes, textures, height fields; URDF meshes). An array of {"path" (relative to `root` when
// under it), "role", "of" (the robot or environment), "sha256"}, sorted by path; a referenced
// file that cannot be read has "sha256": null.
struct LoadedModels {
  const core::RobotProfile* robot = nullptr;
  const core::EnvironmentSpec* environment = nullptr;
};
nlohmann::json model_files_provenance(const std::vector<LoadedModels>& scenes,
                                      const std::filesystem::path& root);

// What defines a run's trial matrix: {"file": the suite or scenario file's absolute path,
// "trials": trials of the whole matrix, "overrides": {"trials", "seed", "planners",
// "execution", "robots", "environments"}} (null or empty where not overridden; a run written
// before 2026-12-06 has no "execution", "robots" or "environments": none overridden).
// load_run_plan(file, ..., replaced_by(o)) + apply_overrides(o), o = overrides_of(...), gives
// the same matrix again.
nlohmann::json matrix_provenance(const RunPlan& plan, const RunOverrides& overrides, size_t trials);
// The overrides of a matrix_provenance() object. Throws core::InputError naming `file`.
RunOverrides overrides_of(const nlohmann::json& matrix, const std::string& file);
// The --execution a run's provenance.json records (matrix.overrides.execution): "" for none,
// nullopt where it records nothing (not a provenance object, or a run written before
// 2026-12-06). A trial's id does not name its execution mode, so resume and compare ask this.
std::optional<std::string> recorded_execution(const nlohmann::json& provenance);
// "--execution MODE", or "the scenarios' own execution modes" for "".
std::string execution_text(const std::string& execution);
// The Slurm job a process runs in: job_id, array_job_id, array_task_id, cluster, partition and
// nodes, from SLURM_* variables; an empty object outside Slurm.
nlohmann::json slurm_provenance();

}  // namespace taskmatrix::harness
