// State machines in YAML (format and rules also in scenarios/README.md):
//
//   name: fetch                      # the program name the machine registers under
//   doc: reach for an object and grasp it
//   parameters:                      # typed: string, number, integer, bool, strings
//     object: {type: string}
//     side: {type: string, default: any, choices: [left, right, any]}
//   concurrent:                      # programs running alongside, started with the machine
//     look: {program: fixate, params: {object: $object}, at_start: true}
//   initial: reach
//   states:
//     reach: {program: reach, params: {object: $object, side: $side}}
//     grasp: {program: grasp, params: {side: $side, object: $object}}
//     done: {final: success}
//     gave_up: {final: failure}
//   transitions:
//     - {from: reach, on: completed, to: grasp}
//     - {from: reach, on: failed, to: gave_up}
//     - {from: grasp, on: completed, to: done, stop: [look]}
#pragma once

#include <filesystem>

#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::io {

// Reads a machine file. Throws core::InputError naming the file, line and key.
core::MachineSpec load_machine_spec(const std::filesystem::path& file);
// Reads, checks against `registry` and registers it. Errors from the check name the file
// and the state or transition (with its line).
void load_and_register_machine(const std::filesystem::path& file, core::ProgramRegistry& registry);
// The same for a machine written inside another document (a scenario's `machine:`).
// Returns the name it registered under.
std::string register_machine_node(const YamlNode& root, core::ProgramRegistry& registry);

}  // namespace taskmatrix::io
