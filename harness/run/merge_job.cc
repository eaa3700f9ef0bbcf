#include "harness/run/merge_job.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <map>
#include <optional>
#include <ostream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "harness/results/json_input.h"
#include "harness/results/provenance.h"
#include "harness/results/run_directory.h"
#include "harness/results/summary.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::harness {

namespace {

using core::InputError;
namespace fs = std::filesystem;

// What must be equal for trials to come from the same build.
constexpr const char* kBuildKeys[] = {"executable_sha256", "mujoco_version", "ompl_version"};
// What the merged provenance takes from the shards: the build that ran the trials.
constexpr const char* kShardBuildKeys[] = {"git_commit",       "git_dirty",      "build",
                                           "compiler",         "mujoco_version", "ompl_version",
                                           "executable_sha256"};

struct ShardDir {
  fs::path dir;
  nlohmann::json provenance;
  Shard shard;
  std::vector<nlohmann::json> trials;  // of this shard's stride of the matrix, in file order
  int other_lines = 0;                 // lines of other matrices or strides, left out
};

std::string provenance_file(const fs::path& dir) { return (dir / "provenance.json").string(); }

ShardDir read_shard(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir.string(), "", "no such shard directory");
  ShardDir s;
  s.dir = dir;
  const std::string file = provenance_file(dir);
  if (!fs::exists(file)) {
    throw InputError(file, "", "missing: not a run directory of taskmatrix run");
  }
  s.provenance = read_json_file(file);  // names the file and line of malformed JSON
  if (!s.provenance.is_object()) throw InputError(file, "", "not a JSON object");
  for (const char* key : {"scenario_hash", "matrix", "shard"}) {
    if (!s.provenance.contains(key)) {
      throw InputError(file, key,
                       "missing: written by a build without sharded runs; run the shard again");
    }
  }
  try {
    const nlohmann::json& sh = s.provenance.at("shard");
    s.shard.index = sh.at("index").get<int>();
    s.shard.count = sh.at("count").get<int>();
    s.shard.from = sh.at("from").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "shard", std::string("unreadable: ") + e.what());
  }
  if (s.shard.count < 1 || s.shard.index < 0 || s.shard.index >= s.shard.count) {
    throw InputError(file, "shard", "index and count do not make a shard");
  }
  return s;
}

// The first shard's value of `key` against another's; throws naming the other's file.
void require_same(const ShardDir& first, const ShardDir& other, const std::string& key,
                  const std::string& what) {
  const nlohmann::json a = first.provenance.value(key, nlohmann::json(nullptr));
  const nlohmann::json b = other.provenance.value(key, nlohmann::json(nullptr));
  if (a != b) {
    throw InputError(provenance_file(other.dir), key,
                     what + ": " + b.dump() + ", but " + first.dir.string() + " has " + a.dump());
  }
}

// The shard's entry in the merged provenance: where and when it ran. Throws core::InputError
// naming its provenance.json when a field has the wrong type.
nlohmann::json shard_record(const ShardDir& s, int trials_merged) {
  const nlohmann::json& p = s.provenance;
  try {
    const std::string end = p.value("finished_at", std::string());
    const nlohmann::json trials = p.value("trials", nlohmann::json::object());
    const nlohmann::json host = p.value("host", nlohmann::json::object());
    nlohmann::json entry = {
        {"dir", fs::absolute(s.dir).lexically_normal().string()},
        {"index", s.shard.index},
        {"count", s.shard.count},
        {"from", s.shard.from},
        {"host", host.value("name", std::string("unknown"))},
        {"cpu", host.value("cpu", std::string("unknown"))},
        {"cores", host.value("cores", nlohmann::json(nullptr))},
        {"started_at", p.value("started_at", std::string())},
        {"finished_at", end.empty() ? nlohmann::json(nullptr) : nlohmann::json(end)},
        {"wall_s", p.value("wall_s", nlohmann::json(nullptr))},
        {"jobs", p.value("jobs", 1)},
        // Killed (no end) or interrupted: its missing trials were never run.
        {"interrupted", end.empty() || trials.value("interrupted", false)},
        {"trials_merged", trials_merged},
        {"other_lines", s.other_lines}};
    if (p.contains("slurm")) entry["slurm"] = p["slurm"];
    return entry;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(provenance_file(s.dir), "", std::string("unreadable: ") + e.what());
  }
}

std::time_t parse_utc(const std::string& iso) {
  std::tm tm{};
  if (strptime(iso.c_str(), "%Y-%m-%dT%H:%M:%SZ", &tm) == nullptr) return -1;
  return timegm(&tm);
}

enum class Transfer { kLinked, kCopied, kMoved };

// Puts `from` at `to`: a hard link, a copy where linking fails (another file system), or with
// `move` a rename (a copy and a removal across file systems).
Transfer transfer(const fs::path& from, const fs::path& to, bool move) {
  std::error_code ec;
  if (move) {
    fs::rename(from, to, ec);
    if (!ec) return Transfer::kMoved;
  } else {
    fs::create_hard_link(from, to, ec);
    if (!ec) return Transfer::kLinked;
  }
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  if (move) fs::remove(from);
  return move ? Transfer::kMoved : Transfer::kCopied;
}

// The model files of all shards (each loads only the scenes of its own trials), sorted by path;
// throws when two shards loaded one file with different contents. null when a shard recorded
// none (an older build).
nlohmann::json merged_model_files(const std::vector<ShardDir>& shards) {
  std::map<std::string, std::pair<nlohmann::json, const ShardDir*>> files;
  for (const ShardDir& s : shards) {
    const nlohmann::json& list = s.provenance.value("model_files", nlohmann::json(nullptr));
    if (!list.is_array()) return nullptr;
    for (const nlohmann::json& f : list) {
      const std::string path = f.value("path", std::string());
      const auto [it, added] = files.emplace(path, std::pair{f, &s});
      if (!added && it->second.first.value("sha256", nlohmann::json()) !=
                        f.value("sha256", nlohmann::json())) {
        throw InputError(provenance_file(s.dir), "model_files",
                         "the shard loaded " + path + " with other contents than " +
                             it->second.second->dir.string() + " (sha256 " +
                             f.value("sha256", nlohmann::json()).dump() + " vs " +
                             it->second.first.value("sha256", nlohmann::json()).dump() + ")");
      }
    }
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [path, f] : files) out.push_back(f.first);
  return out;
}

}  // namespace

MergeJobResult run_merge_job(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                             const MergeJobOptions& options, std::ostream& out, std::ostream& err) {
  const auto t_start = std::chrono::steady_clock::now();
  const std::string merge_started = utc_now_iso();
  if (options.shard_dirs.empty()) throw InputError("merge", "", "needs at least one SHARD_DIR");

  // 1. The shards' provenance: one suite, one build, one matrix.
  std::vector<ShardDir> shards;
  for (const fs::path& dir : options.shard_dirs) shards.push_back(read_shard(dir));
  const ShardDir& first = shards.front();
  for (const ShardDir& s : shards) {
    if (fs::exists(options.out) && fs::equivalent(s.dir, options.out)) {
      throw InputError(options.out.string(), "OUT", "is one of the shard directories");
    }
    require_same(first, s, "scenario_hash", "the shard ran other scenario files");
    for (const char* key : kBuildKeys) require_same(first, s, key, "the shard ran another build");
    require_same(first, s, "matrix", "the shard ran another matrix");
  }
  const nlohmann::json model_files = merged_model_files(shards);

  // 2. The matrix, from the suite the shards ran (still the same files).
  const nlohmann::json& matrix_info = first.provenance["matrix"];
  const std::string first_file = provenance_file(first.dir);
  if (!matrix_info.is_object() || !matrix_info.contains("file") ||
      !matrix_info["file"].is_string()) {
    throw InputError(first_file, "matrix.file", "missing");
  }
  const fs::path suite_file = matrix_info["file"].get<std::string>();
  if (!fs::is_regular_file(suite_file)) {
    throw InputError(suite_file.string(), "",
                     "the suite the shards ran (" + first_file + ": matrix.file) is not there");
  }
  const RunOverrides overrides = overrides_of(matrix_info, first_file);
  RunPlan plan = load_run_plan(suite_file, catalog, registry, replaced_by(overrides));
  apply_overrides(plan, overrides);
  const std::string hash = "sha256:" + plan_hash(plan);
  if (first.provenance["scenario_hash"] != hash) {
    throw InputError(suite_file.string(), "",
                     "its scenario files changed since the shards ran (" +
                         first.provenance["scenario_hash"].dump() + ", now " + hash + ")");
  }
  const std::vector<TrialSpec> matrix = trial_matrix(plan);
  if (matrix_info.value("trials", nlohmann::json(nullptr)) != matrix.size()) {
    throw InputError(first_file, "matrix.trials",
                     "the shards' matrix has " +
                         matrix_info.value("trials", nlohmann::json()).dump() + " trials, but " +
                         suite_file.string() + " with its overrides makes " +
                         std::to_string(matrix.size()));
  }
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < matrix.size(); ++i) index_of[matrix[i].id] = i;

  // 3. Each shard's trials of its own stride.
  std::vector<std::vector<std::pair<size_t, nlohmann::json*>>> found(matrix.size());
  for (size_t k = 0; k < shards.size(); ++k) {
    ShardDir& s = shards[k];
    const fs::path file = s.dir / "trials.jsonl";
    TrialsFile f = read_trials_file(file);
    for (size_t line = 0; line < f.trials.size(); ++line) {
      nlohmann::json& t = f.trials[line];
      if (!t["trial_id"].is_string()) {
        throw InputError(file.string(), "line " + std::to_string(line + 1) + ": trial_id",
                         "not a string");
      }
      const auto it = index_of.find(t["trial_id"].get<std::string>());
      if (it == index_of.end() ||
          it->second % static_cast<size_t>(s.shard.count) != static_cast<size_t>(s.shard.index)) {
        ++s.other_lines;
        continue;
      }
      if (t.contains("trajectory") && !t["trajectory"].is_null()) {
        const std::string expected = "trajectories/" + it->first + ".traj.gz";
        if (t["trajectory"] != expected) {
          throw InputError(file.string(), "line " + std::to_string(line + 1) + ": trajectory",
                           "expected \"" + expected + "\"");
        }
        if (!fs::is_regular_file(s.dir / expected)) {
          throw InputError((s.dir / expected).string(), "",
                           "missing: the trajectory of trial " + it->first);
        }
      }
      s.trials.push_back(std::move(t));
    }
  }
  for (size_t k = 0; k < shards.size(); ++k) {
    for (nlohmann::json& t : shards[k].trials) {
      found[index_of.at(t["trial_id"].get<std::string>())].push_back({k, &t});
    }
  }

  MergeJobResult result;
  result.planned = static_cast<int>(matrix.size());
  const bool one_count = std::all_of(shards.begin(), shards.end(), [&](const ShardDir& s) {
    return s.shard.count == first.shard.count;
  });
  for (size_t i = 0; i < matrix.size(); ++i) {
    if (found[i].empty()) result.missing.push_back(matrix[i].id);
    if (found[i].size() > 1) result.duplicated.push_back(matrix[i].id);
  }
  if (!result.missing.empty() || !result.duplicated.empty()) {
    for (size_t i = 0; i < matrix.size(); ++i) {
      if (found[i].empty()) {
        err << "taskmatrix: merge: missing " << matrix[i].id;
        if (one_count) {
          err << " (shard " << i % static_cast<size_t>(first.shard.count) << "/"
              << first.shard.count << ")";
        }
        err << "\n";
      } else if (found[i].size() > 1) {
        err << "taskmatrix: merge: duplicated " << matrix[i].id << " (in";
        for (const auto& [k, t] : found[i]) err << " " << shards[k].dir.string();
        err << ")\n";
      }
    }
    err << "taskmatrix: merge: " << result.missing.size() << " of " << matrix.size()
        << " trials missing, " << result.duplicated.size() << " duplicated";
    if (!options.allow_partial) {
      err << "; nothing written (--allow-partial merges what is there)\n";
      return result;
    }
    err << "; merging the rest (--allow-partial)\n";
  }

  // The sharded run's span and the shards' own records (read before anything is written).
  std::vector<int> from_shard(shards.size(), 0);
  for (size_t i = 0; i < matrix.size(); ++i) {
    if (!found[i].empty()) ++from_shard[found[i].front().first];
  }
  std::string started, finished;
  int jobs = 0;
  bool unfinished_shard = false;
  nlohmann::json shard_list = nlohmann::json::array();
  for (size_t k = 0; k < shards.size(); ++k) {
    nlohmann::json entry = shard_record(shards[k], from_shard[k]);
    const std::string s_start = entry["started_at"], s_end = entry.value("finished_at", "");
    if (!s_start.empty() && (started.empty() || s_start < started)) started = s_start;
    if (s_end > finished) finished = s_end;
    jobs += entry["jobs"].get<int>();
    unfinished_shard = unfinished_shard || entry["interrupted"].get<bool>();
    shard_list.push_back(std::move(entry));
  }
  const std::time_t t0 = parse_utc(started), t1 = parse_utc(finished);
  const double span_s = t0 >= 0 && t1 >= t0 ? static_cast<double>(t1 - t0) : 0.0;

  // 4. Write OUT as a run writes its directory.
  result.dir = options.out;
  const RunDirectoryLock lock(result.dir, options.command_line, "OUT");
  lock.remove_previous_results();
  std::filesystem::create_directories(result.dir / "trajectories");
  std::vector<nlohmann::json> merged;
  std::map<Transfer, int> transfers;
  std::string lines;
  for (size_t i = 0; i < matrix.size(); ++i) {
    if (found[i].empty()) continue;
    const auto [k, t] = found[i].front();
    if (t->contains("trajectory") && (*t)["trajectory"].is_string()) {
      const std::string rel = (*t)["trajectory"].get<std::string>();
      ++transfers[transfer(shards[k].dir / rel, result.dir / rel, options.move_trajectories)];
    }
    lines += json_text(*t) + "\n";
    result.successes += t->value("success", false) ? 1 : 0;
    merged.push_back(std::move(*t));
  }
  write_file_atomically(result.dir / "trials.jsonl", lines);
  result.merged = static_cast<int>(merged.size());

  nlohmann::json provenance =
      make_provenance(plan, catalog.root(), options.command_line, jobs, mujoco_version());
  for (const char* key : kShardBuildKeys) {
    provenance[key] = first.provenance.value(key, nlohmann::json(nullptr));
  }
  provenance["model_files"] = model_files;
  provenance["matrix"] = matrix_info;
  provenance["shard"] = {{"index", 0}, {"count", 1}, {"from", "merge"}, {"trials", matrix.size()}};
  provenance["started_at"] = started;
  provenance["finished_at"] = finished;
  provenance["wall_s"] = span_s;
  const bool interrupted = !result.missing.empty() && unfinished_shard;
  provenance["trials"] = {{"planned", result.planned},
                          {"finished", result.merged},
                          {"missing", result.missing.size()},
                          {"duplicated", result.duplicated.size()},
                          {"interrupted", interrupted}};
  provenance["shards"] = shard_list;
  const double merge_s = core::seconds_since(t_start);
  provenance["merge"] = {{"host", host_name()},
                         {"started_at", merge_started},
                         {"finished_at", utc_now_iso()},
                         {"wall_s", merge_s},
                         {"allow_partial", options.allow_partial},
                         {"trajectories",
                          {{"linked", transfers[Transfer::kLinked]},
                           {"copied", transfers[Transfer::kCopied]},
                           {"moved", transfers[Transfer::kMoved]}}},
                         {"missing", result.missing},
                         {"duplicated", result.duplicated}};
  const RunInfo info{plan.name, plan.doc, result.planned, interrupted, span_s, jobs};
  out << write_run_results(result.dir, plan, info, merged, provenance);
  return result;
}

}  // namespace taskmatrix::harness
