// What one trial measured (harness/run/trial.h runs it; harness/results/trial_record.h writes
// it as a line of trials.jsonl). Plain data: reading, comparing and reporting on results needs
// no backend. The work record is core's; the state recording (for replays) is the backend's
// (taskmatrix/mujoco/work_record.h: plain structs of numbers and strings, no MuJoCo types).
#pragma once

#include <string>
#include <vector>

#include "taskmatrix/core/executive.h"
#include "taskmatrix/core/task_variation.h"
#include "taskmatrix/core/work_record.h"
#include "taskmatrix/mujoco/work_record.h"

namespace taskmatrix::harness {

// A message of the trial's executive other than planning (started, completed, failed,
// halted), i.e. the programs' and state machines' events, with simulated time.
struct TrialEvent {
  double time_s = 0;
  int sender = -1;
  std::string program;
  std::string type;
  std::string reason;
  std::string path;  // of a state machine's failure (core::Message::path)
};

struct TrialResult {
  bool success = false;
  // "success", or the failure's status: the reason's prefix after any path through state
  // machines ("ik_failure", "collision", ...), "setup_failed", "time_limit" (still running at
  // the limit), "criterion_false" (the program completed but the success condition does not
  // hold: the reason says which clause and what was measured), "invalid_input",
  // "program_error" (a program threw; the trial goes on, the worker lives).
  std::string status;
  std::string failure_reason;
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
  mujoco::StateRecording recording;  // empty unless asked for
  std::vector<std::string> removed_debris;
  core::TrialLayout layout;  // the drawn world: task variation and obstacles
};

}  // namespace taskmatrix::harness
