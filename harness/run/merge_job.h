// `taskmatrix merge OUT SHARD_DIR...`: unions the run directories of a sharded run (`run
// --shard I/N`, harness/scenario/trial_matrix.h) into one run directory, as if one machine had run
// the whole matrix.
//
// Before anything is written it checks that every shard directory comes from
//   - the same suite: the SHA-256 of the scenario files (provenance `scenario_hash`), which
//     must also be that of the files at the suite's recorded path, read again here;
//   - the same build: the executable's SHA-256 and the MuJoCo and OMPL versions;
//   - the same matrix: suite file, overrides (--trials, --seed, --planners) and trial count;
// and that every trial id of the matrix is present exactly once (a shard contributes the
// trials of its own stride; lines of other matrices are left out as `compare` does). Missing
// or duplicated ids are listed and nothing is written, unless `allow_partial` (then the first
// copy of a duplicate, in the order the directories were given, is kept).
//
// OUT is written by the same code as a run's directory (harness/run/run_job.h): trials.jsonl in
// matrix order, summary.json/summary.md recomputed from the trials, one ompl.log, planner
// comparisons with several planners, and provenance.json with the shards' build, each
// shard's directory, host, Slurm ids and times, and the merge's own host and times.
// Trajectories are hard-linked (copied across file systems) or, with `move_trajectories`,
// moved. OUT is itself a valid input to merge (the whole matrix as shard 0/1).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::harness {

struct MergeJobOptions {
  std::filesystem::path out;
  std::vector<std::filesystem::path> shard_dirs;
  bool allow_partial = false;
  bool move_trajectories = false;
  std::vector<std::string> command_line;
};

struct MergeJobResult {
  std::filesystem::path dir;  // empty when nothing was written
  int planned = 0, merged = 0, successes = 0;
  std::vector<std::string> missing, duplicated;  // trial ids, in matrix order
};

// Throws core::InputError (nothing written) for an unreadable or mismatched shard directory
// or suite. Missing or duplicated trials without `allow_partial` are listed on `err` and the
// result has an empty dir. Prints the merged summary on `out`.
MergeJobResult run_merge_job(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                             const MergeJobOptions& options, std::ostream& out, std::ostream& err);

}  // namespace taskmatrix::harness
