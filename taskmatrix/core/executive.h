// The executive: runs task programs at the control rate on one skillset. Each tick it
// updates the perceptual model (when due), steps every running program in start order, and
// advances simulated time by one control period.
//
// Chains: a program holds the chains it declares for as long as it runs; programs on
// disjoint chains run concurrently. Rule for conflicts: a program whose chains are held by
// another running program is refused; it fails at once with reason
// "chains_busy: <chain> held by <program>#<id>", and the running program is not disturbed.
// Perception: the model is updated at the perception rate, and also at the start of the tick
// after any program ends, so that decisions taken on its final message (a state machine's
// guards) see the world as that program left it.
// Forced termination (halt) stops a program's children first, holds its chains where they
// are, frees them, and reports "halted".
// Containment: an exception a program throws (choosing its chains, starting, stepping,
// halting) fails that program, never the caller: std::invalid_argument as
// "invalid_input: ...", anything else as "program_error: <program>: <what>".
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "taskmatrix/core/task_program.h"

namespace taskmatrix::core {

// A time series a program recorded (ProgramContext::record).
struct RecordedSeries {
  int instance = -1;
  std::string program;  // the instance's program type
  std::string name;
  std::vector<std::pair<double, double>> samples;  // (simulated time, value)
};

struct ExecutiveOptions {
  double perception_rate_hz = 10.0;
  PlanOptions plan;        // planner, time limit, ...; seeds come from `seed`
  std::uint32_t seed = 1;  // > 0; every plan request draws the next seed of this sequence
};

class Executive {
 public:
  // `perception` may be null (the model is then written by the caller).
  Executive(Skillset& skills, const ProgramRegistry& registry, Perception* perception,
            ExecutiveOptions options = {});
  ~Executive();
  Executive(const Executive&) = delete;
  Executive& operator=(const Executive&) = delete;

  // Starts a registered program; returns its instance id. Throws std::invalid_argument for
  // an unknown program or bad parameters, before anything runs.
  int start(const std::string& program, const RawParams& params);
  // Starts an already built program under `name`.
  int start(std::unique_ptr<TaskProgram> program, const std::string& name);
  void halt(int id);

  void tick();
  // Ticks until no program runs or `max_time_s` of simulated time has passed since the call.
  // Returns true if every program ended.
  bool run(double max_time_s);

  bool running(int id) const;
  bool any_running() const;
  // The final message of an ended program (completed, failed or halted); null while it runs.
  const Message* outcome(int id) const;
  const std::vector<Message>& log() const { return log_; }
  // Every series recorded so far, in order of first sample.
  const std::vector<RecordedSeries>& series() const { return series_; }
  // The series `name` of the first instance of `program` that recorded one; null if none.
  const RecordedSeries* find_series(const std::string& program, const std::string& name) const;
  int holder_of_chain(const std::string& chain) const;  // -1 if free
  PerceptualModel& percepts() { return percepts_; }
  const ProgramRegistry& registry() const { return registry_; }
  Skillset& skills() { return skills_; }
  // Brings the perceptual model up to date now.
  void perceive();

 private:
  class Context;
  struct Instance;
  int launch(std::unique_ptr<TaskProgram> program, const std::string& name, int parent);
  void emit(int id, MessageType type, std::optional<Failure> failure = std::nullopt,
            std::shared_ptr<const PlanResult> plan = nullptr);
  std::uint32_t next_seed();
  void finish(int id, MessageType type, std::optional<Failure> failure = std::nullopt);
  // Runs `what` (a call into program `id`); an exception fails the program (see above).
  // Returns false if it threw.
  template <typename F>
  bool contained(int id, F&& what);

  Skillset& skills_;
  const ProgramRegistry& registry_;
  Perception* perception_;
  ExecutiveOptions options_;
  PerceptualModel percepts_;
  std::map<int, std::unique_ptr<Instance>> instances_;
  std::map<std::string, int> chain_holder_;
  std::vector<Message> log_;
  std::vector<RecordedSeries> series_;
  std::map<std::string, std::vector<std::string>> notes_;  // ProgramContext::notes
  bool refresh_percepts_ = false;  // a program ended: perceive before the next steps
  int next_id_ = 1;
  std::uint64_t seed_counter_ = 0;
  double next_perception_ = 0;
};

}  // namespace taskmatrix::core
