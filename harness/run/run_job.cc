#include "harness/run/run_job.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <map>
#include <ostream>
#include <set>

#include "harness/backends/backends.h"
#include "harness/compare/planner_comparison.h"
#include "harness/compare/power.h"
#include "harness/replay/trajectory_file.h"
#include "harness/results/json_input.h"
#include "harness/results/layout_json.h"
#include "harness/results/ompl_log.h"
#include "harness/results/provenance.h"
#include "harness/results/run_directory.h"
#include "harness/results/summary.h"
#include "harness/results/trial_record.h"
#include "harness/run/trial.h"
#include "harness/run/worker_pool.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/io/text_file.h"

namespace taskmatrix::harness {

namespace {

using Clock = std::chrono::steady_clock;
using SceneMap =
    std::map<std::pair<std::string, std::string>, std::shared_ptr<const core::LoadedScene>>;

constexpr size_t kMaxTrialIdLength = 200;

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_stop_signal(int) { g_stop = 1; }

class StopSignals {
 public:
  StopSignals() {
    g_stop = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

struct Prepared {
  RunPlan plan;
  std::vector<TrialSpec> matrix;  // of the shard
  size_t whole_matrix = 0;        // trials of the whole matrix
  SceneMap scenes;
  std::map<std::string, core::TrialLayout> layouts;  // by trial id
};

// Loads the plan and every scene it needs, and draws every trial's layout once, so that a
// bad file, model or layout request stops the run before anything is written.
Prepared prepare(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                 const std::filesystem::path& file, const RunOverrides& overrides,
                 const std::string& only, const Shard& shard) {
  Prepared p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw core::InputError(file.string(), "", "no such scenario or suite file");
  }
  p.plan = load_run_plan(file, catalog, registry, replaced_by(overrides));
  apply_overrides(p.plan, overrides);
  if (only.empty()) {
    p.matrix = trial_matrix(p.plan);
    p.whole_matrix = p.matrix.size();
    if (shard.count > 1) p.matrix = select_shard(p.matrix, shard);
  } else {
    p.matrix = {parse_trial_id(p.plan, only)};
    p.whole_matrix = 1;
  }
  // Each scenario's names against each of its environments, once.
  std::set<std::pair<int, std::string>> names_checked;
  for (const TrialSpec& t : p.matrix) {
    // The id names the trial's trajectory file (at most 255 bytes with its suffix).
    if (t.id.size() > kMaxTrialIdLength) {
      throw core::InputError(
          p.plan.scenarios[static_cast<size_t>(t.scenario)].file.string(), "name",
          "trial id '" + t.id.substr(0, 60) + "...' has " + std::to_string(t.id.size()) +
              " characters (at most " + std::to_string(kMaxTrialIdLength) +
              "): shorten the scenario, robot, environment or planner names");
    }
    auto& scene = p.scenes[{t.robot, t.environment}];
    if (!scene) {
      scene = backend().load(catalog.robot_dir(t.robot), catalog.environment_dir(t.environment));
    }
    const Scenario& s = p.plan.scenarios[static_cast<size_t>(t.scenario)];
    if (names_checked.insert({t.scenario, t.environment}).second) {
      check_names(s, scene->environment());
    }
    p.layouts[t.id] = draw_trial_layout(s, *scene, t.layout_seed, t.id);
  }
  return p;
}

std::string format_duration(double s) {
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600),
                  static_cast<int>(s / 60) % 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  }
  return buf;
}

// Appends one line and makes it durable before the next trial is reported.
class TrialsWriter {
 public:
  explicit TrialsWriter(const std::filesystem::path& file) {
    fd_ = open(file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error(file.string() + ": cannot open for appending");
  }
  ~TrialsWriter() {
    if (fd_ >= 0) close(fd_);
  }
  TrialsWriter(const TrialsWriter&) = delete;
  TrialsWriter& operator=(const TrialsWriter&) = delete;
  void append(const std::string& line) {
    const std::string text = line + "\n";
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = write(fd_, text.data() + done, text.size() - done);
      if (n < 0) throw std::runtime_error("trials.jsonl: write failed");
      done += static_cast<size_t>(n);
    }
    fdatasync(fd_);
  }

 private:
  int fd_ = -1;
};

// A directory --resume may continue: its provenance (when there is one) must be an object
// from the same scenario files, run in the same execution mode (a trial's id does not say it:
// its trials would pass for this run's).
void check_resumable(const std::filesystem::path& dir, const std::string& hash,
                     const std::string& execution) {
  const std::filesystem::path prov = dir / "provenance.json";
  std::error_code ec;
  if (!std::filesystem::exists(prov, ec)) return;
  const nlohmann::json old = read_json_file(prov);
  const JsonPlace where{prov.string(), 0, ""};
  if (!old.is_object()) where.fail("must be a JSON object");
  const nlohmann::json& old_hash =
      json_optional_field(old, "scenario_hash", JsonKind::kString, where);
  if (old_hash.is_string() && old_hash.get<std::string>() != hash) {
    throw core::InputError(dir.string(), "--resume",
                           "the run there was made from different scenario files (" +
                               old_hash.get<std::string>() + ", now " + hash +
                               "); choose another --out");
  }
  // Older directories record no execution mode and are not checked.
  const std::optional<std::string> was = recorded_execution(old);
  if (was && *was != execution) {
    throw core::InputError(dir.string(), "--resume",
                           "the run there ran with " + execution_text(*was) + ", now " +
                               execution_text(execution) + "; choose another --out");
  }
}

OmplLogInfo ompl_info(const RunPlan& plan, const nlohmann::json& provenance, double total_s) {
  OmplLogInfo info;
  info.experiment = plan.name;
  info.setup = plan.suite ? plan.text : "";
  for (const Scenario& s : plan.scenarios)
    info.setup += "# " + s.file.string() + "\n" + s.file_text;
  info.hostname = host_name();
  info.cpuinfo = cpu_model();
  info.date = provenance.value("started_at", utc_now_iso());
  info.seed = plan.scenarios.empty() ? 1 : plan.scenarios[0].seed;
  for (const Scenario& s : plan.scenarios)
    info.time_limit_s = std::max(info.time_limit_s, s.wall_limit_s);
  info.total_time_s = total_s;
  for (const Scenario& s : plan.scenarios) {
    for (const PlannerConfig& pc : s.planners) {
      const bool seen =
          std::any_of(info.planners.begin(), info.planners.end(),
                      [&](const OmplLogInfo::Planner& q) { return q.label == pc.label; });
      if (seen) continue;
      OmplLogInfo::Planner p{pc.label, pc.spec.name, {}};
      for (const auto& [k, v] : pc.spec.params) p.params.emplace_back(k, v);
      info.planners.push_back(std::move(p));
    }
  }
  return info;
}

}  // namespace

std::string write_run_results(const std::filesystem::path& dir, const RunPlan& plan,
                              const RunInfo& info, const std::vector<nlohmann::json>& finished,
                              const nlohmann::json& provenance) {
  nlohmann::json summary = make_summary(info, finished);
  // What `compare` pairs: trials.jsonl may also hold another matrix's trials (--resume).
  nlohmann::json ids = nlohmann::json::array();
  for (const nlohmann::json& t : finished) ids.push_back(t.value("trial_id", std::string()));
  summary["trial_ids"] = std::move(ids);
  // Several planners: each against the first, on the same trials.
  std::vector<std::string> planners;
  for (const Scenario& s : plan.scenarios) {
    for (const PlannerConfig& pc : s.planners) {
      if (std::find(planners.begin(), planners.end(), pc.label) == planners.end()) {
        planners.push_back(pc.label);
      }
    }
  }
  const std::vector<Comparison> vs_reference =
      compare_planners(finished, planners, planner_budgets(plan));
  std::string appendix;
  if (!vs_reference.empty()) {
    nlohmann::json comparisons = nlohmann::json::array();
    for (const Comparison& c : vs_reference) comparisons.push_back(comparison_json(c));
    summary["planner_comparison"] = {{"reference", planners[0]}, {"comparisons", comparisons}};
    appendix = planner_table_markdown(finished, planners, vs_reference);
    write_planner_comparison(dir, plan.name, finished, planners, vs_reference);
  }
  summary["power"] = summary_power_json(summary);
  appendix += summary_power_markdown(summary["power"]);
  write_summary(dir, summary, appendix);
  write_file_atomically(dir / "ompl.log",
                        ompl_log_text(ompl_info(plan, provenance, info.wall_s), finished));
  write_file_atomically(dir / "provenance.json", json_text(provenance, 2) + "\n");
  return summary_markdown(summary) + appendix;
}

int validate_run_plan(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                      const std::filesystem::path& file, std::vector<std::string>* warnings) {
  const Prepared p = prepare(catalog, registry, file, {}, "", {});
  if (warnings) {
    // Every machine a scenario runs, and the machines those run, once each.
    std::set<std::string> seen;
    std::vector<std::string> pending;
    for (const Scenario& s : p.plan.scenarios) {
      pending.push_back(s.run.program);
      for (const ProgramCall& c : s.setup) pending.push_back(c.program);
    }
    while (!pending.empty()) {
      const std::string program = pending.back();
      pending.pop_back();
      const core::ProgramType* type = registry.find(program);
      if (!type || !type->machine || !seen.insert(program).second) continue;
      const core::MachineSpec& m = *type->machine;
      for (const std::string& w : core::machine_warnings(m)) {
        warnings->push_back((m.source.empty() ? "built in" : m.source) + ": warning: " + w);
      }
      for (const core::MachineState& st : m.states) {
        if (!st.final) pending.push_back(st.program);
      }
      for (const core::ConcurrentProgram& c : m.concurrent) pending.push_back(c.program);
    }
  }
  return static_cast<int>(p.matrix.size());
}

RunJobResult run_job(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                     const RunJobOptions& options, std::ostream& out, std::ostream& err) {
  const Clock::time_point t_start = Clock::now();
  if (options.jobs < 1 || options.jobs > 256)
    throw core::InputError("--jobs", "", "must be in 1..256");
  if (!options.only.empty() && options.shard.count > 1) {
    throw core::InputError("--shard", "", "runs a shard of the matrix; --only runs one trial");
  }
  Prepared p = prepare(catalog, registry, options.scenario_file, options.overrides, options.only,
                       options.shard);
  const RunPlan& plan = p.plan;
  RunJobResult result;
  result.planned = static_cast<int>(p.matrix.size());
  for (const Scenario& s : p.plan.scenarios) result.scenarios.push_back(s.name);

  const bool write_dir = options.only.empty() || !options.out.empty();
  if (write_dir) {
    // Shards default to directories of their own, so that they never write into each other.
    const std::string name = options.shard.count > 1
                                 ? plan.name + "-shard-" + std::to_string(options.shard.index) +
                                       "-of-" + std::to_string(options.shard.count)
                                 : plan.name;
    result.dir = options.out.empty() ? catalog.root() / "results" / "runs" / name : options.out;
  }
  const std::filesystem::path trials_file = result.dir / "trials.jsonl";
  const std::string hash = "sha256:" + plan_hash(plan);
  std::vector<nlohmann::json> kept;
  std::error_code ec;
  if (write_dir && !options.only.empty() && std::filesystem::exists(trials_file, ec)) {
    throw core::InputError(result.dir.string(), "--out",
                           "holds a run; --only writes only into a new directory");
  }
  // Everything in the directory is read and checked before anything is written, and again
  // once the directory is locked (another run may have ended in between).
  auto read_resumed = [&] {
    if (!write_dir || !options.resume) return;
    check_resumable(result.dir, hash, options.overrides.execution);
    TrialsFile existing = read_trials_file(trials_file);
    if (existing.torn_tail) {
      std::filesystem::resize_file(trials_file, existing.valid_bytes);
      err << "taskmatrix: resume: dropped a torn last line of " << trials_file.string() << "\n";
    }
    if (!existing.duplicates.empty()) {
      err << "taskmatrix: resume: " << describe_duplicates(trials_file, existing) << "\n";
    }
    // Trials of another matrix (other --trials, --planners or --seed) stay in the file but
    // are not part of this run's summary.
    std::set<std::string> ids;
    for (const TrialSpec& t : p.matrix) ids.insert(t.id);
    kept.clear();
    for (nlohmann::json& t : existing.trials) {
      if (ids.count(t["trial_id"].get<std::string>())) kept.push_back(std::move(t));
    }
  };
  if (write_dir && options.resume) {
    check_resumable(result.dir, hash, options.overrides.execution);
    read_trials_file(trials_file);  // throws on a bad line; changes nothing
  }
  std::unique_ptr<RunDirectoryLock> lock;
  if (write_dir) {
    lock = std::make_unique<RunDirectoryLock>(result.dir, options.command_line);
    read_resumed();
    std::filesystem::create_directories(result.dir / "trajectories");
    if (!options.resume) lock->remove_previous_results();
  }
  std::set<std::string> done;
  for (const nlohmann::json& t : kept) done.insert(t["trial_id"].get<std::string>());
  std::vector<const TrialSpec*> pending;
  for (const TrialSpec& t : p.matrix) {
    if (!done.count(t.id)) pending.push_back(&t);
  }

  nlohmann::json provenance =
      make_provenance(plan, catalog.root(), options.command_line, options.jobs, mujoco_version());
  provenance["matrix"] = matrix_provenance(plan, options.overrides, p.whole_matrix);
  std::vector<LoadedModels> loaded;
  for (const auto& [names, scene] : p.scenes) {
    loaded.push_back({&scene->robot(), &scene->environment()});
  }
  provenance["model_files"] = model_files_provenance(loaded, catalog.root());
  provenance["shard"] = {{"index", options.shard.index},
                         {"count", options.shard.count},
                         {"from", options.shard.from},
                         {"trials", p.matrix.size()}};
  if (const nlohmann::json slurm = slurm_provenance(); !slurm.empty()) provenance["slurm"] = slurm;
  if (write_dir)
    write_file_atomically(result.dir / "provenance.json", json_text(provenance, 2) + "\n");

  const bool progress =
      options.progress == RunJobOptions::Progress::kOn ||
      (options.progress == RunJobOptions::Progress::kAuto && isatty(STDERR_FILENO));
  std::unique_ptr<TrialsWriter> writer;
  if (write_dir) writer = std::make_unique<TrialsWriter>(trials_file);
  std::vector<nlohmann::json> finished = kept;
  int successes = 0;
  for (const nlohmann::json& t : kept) successes += t.value("success", false) ? 1 : 0;
  const bool keep_trajectories = write_dir && options.record_rate_hz > 0;

  auto work = [&](size_t i) -> std::string {
    const TrialSpec& t = *pending[i];
    const Scenario& s = plan.scenarios[static_cast<size_t>(t.scenario)];
    const auto& scene = p.scenes.at({t.robot, t.environment});
    TrialOptions topt;
    topt.planner = &s.planners[static_cast<size_t>(t.planner)];
    topt.record_rate_hz = keep_trajectories ? options.record_rate_hz : 0;
    topt.layout = &p.layouts.at(t.id);
    const TrialResult r = run_trial(s, *scene, t.layout_seed, t.seed, registry, nullptr, topt);
    nlohmann::json j = trial_json(plan, t, r);
    if (keep_trajectories) {
      TrajectoryFile file;
      file.robot = t.robot;
      file.environment = t.environment;
      file.layout = r.layout.obstacles;
      file.variation = r.layout.variation;
      file.recording = r.recording;
      file.removed_bodies = r.removed_debris;
      const std::string rel = "trajectories/" + t.id + ".traj.gz";
      write_trajectory_file(result.dir / rel, file);
      j["trajectory"] = rel;
      j["trajectory_frames"] = r.recording.frames();
    }
    return json_text(j);
  };
  auto wall_limit = [&](size_t i) {
    return plan.scenarios[static_cast<size_t>(pending[i]->scenario)].wall_limit_s;
  };
  const Clock::time_point t_trials = Clock::now();
  int ran = 0;
  auto on_done = [&](size_t i, const WorkerOutcome& o) {
    const TrialSpec& t = *pending[i];
    nlohmann::json j;
    if (o.has_result) {
      j = nlohmann::json::parse(o.payload, nullptr, false);
      if (j.is_discarded()) {
        j = failed_trial_json(
            plan, t, core::Failure(core::FailureCode::kCrash, "the worker's result is not JSON"));
      }
    } else {
      j = failed_trial_json(plan, t, o.failure);
      j["layout"] = layout_json(p.layouts.at(t.id));
    }
    j["wall_time_s"] = o.wall_s;
    j["peak_memory_mb"] = o.peak_memory_mb;
    j["cpu_time_s"] = o.cpu_s;
    // What the harness adds to the trial: the worker's wall time outside the executive
    // (fork, the worker's skillset and layout, judging success, the result and trajectory).
    j["overhead_s"] = j["executive_wall_s"].is_number()
                          ? nlohmann::json(o.wall_s - j["executive_wall_s"].get<double>())
                          : nlohmann::json(nullptr);
    const std::string line = json_text(j);
    if (writer) writer->append(line);
    if (!options.only.empty()) out << line << "\n" << std::flush;
    successes += j.value("success", false) ? 1 : 0;
    finished.push_back(std::move(j));
    ++ran;
    if (progress) {
      const double elapsed = core::seconds_since(t_trials);
      const double eta =
          elapsed / ran * static_cast<double>(pending.size() - static_cast<size_t>(ran));
      char buf[200];
      std::snprintf(buf, sizeof buf, "\r[%zu/%d] success %d/%zu (%.0f%%)  elapsed %s  ETA %s   ",
                    finished.size(), result.planned, successes, finished.size(),
                    100.0 * successes / static_cast<double>(finished.size()),
                    format_duration(elapsed).c_str(), format_duration(eta).c_str());
      err << buf << std::flush;
    }
  };

  {
    StopSignals signals;
    WorkerPoolOptions pool;
    pool.jobs = options.jobs;
    pool.stop = &g_stop;
    pool.in_worker = [] { backend().on_fatal_error(crash_worker); };
    run_in_workers(pending.size(), pool, work, wall_limit, on_done);
    result.interrupted = g_stop != 0;
  }
  if (progress) err << "\n";
  writer.reset();
  result.ran = ran;
  result.finished = static_cast<int>(finished.size());
  result.successes = successes;
  const double wall = core::seconds_since(t_start);
  if (write_dir) {
    provenance["finished_at"] = utc_now_iso();
    provenance["wall_s"] = wall;
    provenance["trials"] = {{"planned", result.planned},
                            {"finished", result.finished},
                            {"ran_now", ran},
                            {"resumed_from", kept.size()},
                            {"interrupted", result.interrupted}};
    const RunInfo info{plan.name, plan.doc, result.planned, result.interrupted, wall, options.jobs};
    const std::string markdown = write_run_results(result.dir, plan, info, finished, provenance);
    if (options.only.empty()) out << markdown;
  }
  return result;
}

std::string mujoco_version() { return backend("mujoco").version(); }

}  // namespace taskmatrix::harness
