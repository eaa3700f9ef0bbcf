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

struct MachineState {
  std::string name;
  std::string program;  // empty for final states
  RawParams params;
  bool final = false;
  bool success = true;    // for final states
  std::string invariant;  // a condition that must hold while the state runs; empty: none
};

struct MachineTransition {
  std::string from;  // a state, or a concurrent program's name
  MessageType on = MessageType::kCompleted;
  std::string to;                  // a state; empty: stay (only start/stop)
  std::vector<std::string> start;  // concurrent programs to (re)start
  std::vector<std::string> stop;   // concurrent programs to halt
  std::string when;                // a guard condition; empty: always
};

struct ConcurrentProgram {
  std::string name;
  std::string program;
  RawParams params;
  bool at_start = true;  // started with the machine
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

}  // namespace taskmatrix::core
