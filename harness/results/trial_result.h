// What one trial measured (harness/run/trial.h runs it; harness/results/trial_record.h writes
// it as a line of trials.jsonl). Plain data: reading, comparing and reporting on results needs
// no backend: the work record and the state recording (for replays) are core's plain structs.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/executive.h"
#include "taskmatrix/core/failure.h"
#include "taskmatrix/core/state_recording.h"
#include "taskmatrix/core/task_variation.h"
#include "taskmatrix/core/work_record.h"

namespace taskmatrix::harness {

// A message of the trial's executive other than planning (started, completed, failed,
// halted), i.e. the programs' and state machines' events, with simulated time.
struct TrialEvent {
  double time_s = 0;
  int sender = -1;
  std::string program;
  std::string type;
  std::string reason;
  std::string path;  // of a state machine's failure (core::Failure::path)
};

struct TrialResult {
  bool success = false;
  // Why the trial failed (nullopt when it succeeded): the program's failure, its path beginning
  // with the program when it happened inside state machines ("fetch > pickup(approach) >
  // reach"); kSetupFailed, kTimeLimit (still running at the limit), kCriterionFalse (the
  // program completed but the success condition does not hold: the detail says which clause
  // and what was measured), kInvalidInput, kProgramError (a program threw; the trial goes on,
  // the worker lives).
  std::optional<core::Failure> failure;
  double duration_s = 0;    // simulated seconds of the scenario's program
  double sim_time_s = 0;    // simulated seconds of the whole trial, set-up included
  double trial_wall_s = 0;  // wall clock inside run_trial, set-up of the skillset included
  // Wall clock inside the executive: set-up programs and the program (their planning, IK,
  // queries, logic and the simulation). trial_wall_s minus this is the trial's set-up.
  double executive_wall_s = 0;
  core::WorkRecord work;  // every plan call, IK, checks, the executed motion
  std::vector<TrialEvent> events;
  std::vector<core::Message> log;  // every message, set-up included
  std::vector<core::RecordedSeries> series;
  core::StateRecording recording;  // empty unless asked for
  std::vector<std::string> removed_debris;
  core::TrialLayout layout;  // the drawn world: task variation and obstacles
};

// The trial record's texts: "success" or the failure's code ("ik_failure"); the failure as a
// user reads it ("fetch > pickup(approach) > reach: ik_failure: ..."), cut at 600 characters
// (the events hold the whole text), "" on success.
std::string trial_status(const TrialResult& result);
std::string trial_failure_reason(const TrialResult& result);

}  // namespace taskmatrix::harness
