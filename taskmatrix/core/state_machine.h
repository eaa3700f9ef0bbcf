// State machines over task programs (paper Fig. 4). A state runs one program with
// parameters; transitions fire on the messages that program (or a concurrent program of the
// machine) emits; a transition may start and stop the machine's concurrent programs; final
// states end the machine with success or failure. A machine is itself a task program, so
// machines nest: register a MachineSpec and use its name as any state's program.
//
// Guards and invariants: a transition may carry a condition (`when`, in parse_condition's
// text form) and fires only if it holds when its message arrives; of several transitions for
// the same message, the first whose guard holds fires. A state may carry an `invariant`,
// checked every step while its program runs: when it stops holding, the program is halted
// and the state fails with "invariant_false: <condition>". Conditions may use "$name".
//
// Parameters: a machine declares typed parameters; state parameters may refer to them as
// "$name". Everything is checked when the machine is registered, before anything runs.
// A state's program failing with no transition for `failed` fails the machine with the
// same reason; every non-final state must have a transition for `completed`. The machine's
// failure message says where (Message::path): the state, as "program(state)", and the path
// inside it when its program is itself a machine, e.g. "greet > postural(lower)".
#pragma once

#include <string>
#include <vector>

#include "taskmatrix/core/task_program.h"

namespace taskmatrix::core {

// Where a machine file wrote a state, transition or concurrent program: its key and line
// (empty and 0 for machines built in code).
struct SourceSpot {
  std::string key = "";
  int line = 0;
};

struct MachineState {
  std::string name;
  std::string program;  // empty for final states
  RawParams params;
  bool final = false;
  bool success = true;    // for final states
  std::string invariant;  // a condition that must hold while the state runs; empty: none
  SourceSpot spot = {};
};

struct MachineTransition {
  std::string from;  // a state, or a concurrent program's name
  MessageType on = MessageType::kCompleted;
  std::string to;                  // a state; empty: stay (only start/stop)
  std::vector<std::string> start;  // concurrent programs to (re)start
  std::vector<std::string> stop;   // concurrent programs to halt
  std::string when;                // a guard condition; empty: always
  SourceSpot spot = {};
};

struct ConcurrentProgram {
  std::string name;
  std::string program;
  RawParams params;
  bool at_start = true;  // started with the machine
  SourceSpot spot = {};
};

struct MachineSpec {
  std::string name;
  std::string doc;
  std::string source;  // file it came from, for messages
  std::vector<ParamSpec> params;
  std::vector<MachineState> states;
  std::string initial;
  std::vector<MachineTransition> transitions;
  std::vector<ConcurrentProgram> concurrent;
};

// Checks the machine against the registry (programs exist, parameters fit their specs,
// "$x" names a machine parameter, states and transitions are consistent). Throws
// std::invalid_argument with a message naming the state or transition at fault.
void check_machine(const MachineSpec& spec, const ProgramRegistry& registry);

// check_machine, then registers the machine as a program type under spec.name.
void register_machine(const MachineSpec& spec, ProgramRegistry& registry);

// What a machine's layout leaves without a way to succeed, for `taskmatrix validate` to warn
// of (each a sentence naming the machine): states no transition leads to from the initial
// state, and no final state with success.
std::vector<std::string> machine_warnings(const MachineSpec& spec);

// A name that a call of a program gives to something in the world: through a parameter whose
// spec says what it names (ParamSpec::names), or as an object argument of a machine's guard
// or invariant (ConditionArgKind::kObject), followed through machines' "$x" references.
struct NameUse {
  std::string name;
  // The call's own parameter it came from ("" when a machine wrote it as it is), and whether
  // that parameter was left at its default.
  std::string param;
  bool defaulted = false;
  // Where it is used: "pickup > reach(reach): parameter 'object'", "tidy, state 'wait'
  // invariant".
  std::string path;
  // Where a machine file wrote it, when it came from no parameter of the call.
  std::string file = "";
  SourceSpot spot = {};
};
// The names the call (`program` with `params`, checked by check_params) gives, in the order
// its machine states and programs declare them. Throws std::invalid_argument as check_params.
std::vector<NameUse> names_used(const ProgramRegistry& registry, const std::string& program,
                                const RawParams& params);

}  // namespace taskmatrix::core
