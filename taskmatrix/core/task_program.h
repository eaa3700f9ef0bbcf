// Task programs (paper section III-D): functions of time and state, with typed parameters
// checked before anything runs, the chains they use, a precondition, and a start / step /
// halt lifecycle driven by the executive at the control rate. They talk to the world only
// through ProgramContext (the skillset, the perceptual model, messages, child programs).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/core/failure.h"
#include "taskmatrix/core/parameters.h"
#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/skillset.h"

namespace taskmatrix::core {

// ---- Parameters (types and specs: parameters.h).
// Checked, typed parameters of one program instance.
class Params {
 public:
  Params() = default;
  explicit Params(std::map<std::string, ParamValue> values) : values_(std::move(values)) {}
  const std::string& text(const std::string& name) const;
  double number(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  bool flag(const std::string& name) const;
  const std::vector<std::string>& list(const std::string& name) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }

 private:
  const ParamValue& at(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

// Parses one value; throws std::invalid_argument with a message naming the expected type.
ParamValue parse_param(const ParamSpec& spec, const std::string& text);
// Checks `raw` against `specs`: unknown names, missing required ones, wrong types and
// choices. Throws std::invalid_argument("parameter 'x': ...").
Params check_params(const std::vector<ParamSpec>& specs, const RawParams& raw);

// ---- Messages.
enum class MessageType { kStarted, kPlanningStarted, kPlanningEnded, kCompleted, kFailed, kHalted };
const char* to_string(MessageType type);
// Throws std::invalid_argument for an unknown name ("completed", "failed", ...).
MessageType message_type_from_string(const std::string& name);

struct Message {
  double time = 0;
  int sender = -1;      // program instance id
  std::string program;  // its program type, e.g. "reach"
  MessageType type = MessageType::kStarted;
  // For kFailed: why, and for a failure of a state machine where in it (and in the machines
  // it runs) it happened (Failure::path, e.g. "greet > postural(lower)"). For kPlanningEnded:
  // the failure of a plan that failed.
  std::optional<Failure> failure;
  // For kPlanningEnded: the plan's result (status, times, work counts, path).
  std::shared_ptr<const PlanResult> plan;
  // The failure's reason ("ik_failure: ..."); "" without a failure.
  std::string reason() const { return failure ? failure->reason() : ""; }
};

// One step of a path: "program" when the state is named after it, else "program(state)".
std::string path_step(const std::string& program, const std::string& state);

enum class ProgramState { kRunning, kCompleted, kFailed };

class TaskProgram;

// What a running program may use.
class ProgramContext {
 public:
  virtual ~ProgramContext() = default;
  virtual Skillset& skills() = 0;
  virtual const PerceptualModel& percepts() const = 0;
  World world() { return World{skills(), percepts()}; }
  virtual double time() const = 0;
  virtual int self() const = 0;  // this program's instance id
  virtual void emit(MessageType type, std::optional<Failure> failure = std::nullopt,
                    std::shared_ptr<const PlanResult> plan = nullptr) = 0;
  // Planner settings and a seed source for this run.
  virtual const PlanOptions& plan_options() const = 0;
  virtual std::uint32_t next_seed() = 0;
  // Child programs (state machines): started with this program as parent; their messages
  // arrive in this program's inbox. start_child returns the child's id; a refused child
  // (chains busy, precondition false) has already sent its kFailed message.
  virtual int start_child(const std::string& program, const RawParams& params) = 0;
  virtual void halt_child(int id) = 0;
  virtual std::vector<Message> take_inbox() = 0;
  // Appends (time(), value) to this program instance's time series `series` (tracking error,
  // coverage, ...), kept by the executive for the run's results.
  virtual void record(const std::string& series, double value) = 0;
  // Notes the programs of one run share (the executive keeps them for its lifetime): what a
  // later program needs to know of an earlier one's outcome, such as the grasps of an object
  // that did not hold. Keys and entries are the programs' own.
  virtual std::vector<std::string>& notes(const std::string& key) = 0;
};

// What a program may consider when it chooses its chains (before it starts).
struct ClaimContext {
  const Skillset& skills;
  const PerceptualModel& percepts;
  std::function<bool(const std::string& chain)> busy;  // held by a running program
  std::uint32_t seed;                                  // for a random choice
  // Whether the robot, these chains at these values and the rest as it stands, touches
  // nothing (Skillset::is_valid): a choice between limbs may prefer the one that fits.
  std::function<bool(const std::vector<std::string>& chains, const std::vector<double>& values)>
      clear;
};

class TaskProgram {
 public:
  virtual ~TaskProgram() = default;
  // Chains this program commands; the executive holds them for it while it runs.
  virtual std::vector<std::string> chains(const Skillset& skills) const = 0;
  // Called by the executive instead of chains() when the program is launched: a program with
  // a choice (which arm, which side to mirror a posture to) makes it here, may record it, and
  // returns its chains. Defaults to chains().
  virtual std::vector<std::string> claim(const ClaimContext& ctx) { return chains(ctx.skills); }
  // May be null. Checked when the program starts; false fails it with kPreconditionFalse.
  virtual ConditionPtr precondition() const { return nullptr; }
  virtual void start(ProgramContext& ctx) = 0;
  virtual ProgramState step(ProgramContext& ctx) = 0;
  // Forced termination: stop commanding motion (hold where the chains are).
  virtual void halt(ProgramContext& ctx);
  // Why step() returned kFailed (with a path, for a state machine).
  const Failure& failure() const { return failure_; }

 protected:
  ProgramState fail(Failure failure) {
    failure_ = std::move(failure);
    return ProgramState::kFailed;
  }
  ProgramState fail(FailureCode code, std::string detail) {
    return fail(Failure(code, std::move(detail)));
  }

 private:
  Failure failure_;
};

// ---- The program registry: names to parameter specs and factories.
struct MachineSpec;  // state_machine.h
struct ProgramType {
  std::string name;
  std::string doc;
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<TaskProgram>(const Params&)> make;
  // The machine it runs, for a program registered by register_machine (else null): what
  // names_used reads through.
  std::shared_ptr<const MachineSpec> machine = nullptr;
};

class ProgramRegistry {
 public:
  // Throws std::invalid_argument if the name is taken.
  void add(ProgramType type);
  const ProgramType* find(const std::string& name) const;
  std::vector<std::string> names() const;
  // check_params + make; throws std::invalid_argument naming the program and parameter.
  std::unique_ptr<TaskProgram> instantiate(const std::string& name, const RawParams& raw) const;

 private:
  std::map<std::string, ProgramType> types_;
};

}  // namespace taskmatrix::core
