// Typed parameters as task programs and planners declare them: a spec per parameter (name,
// type, whether required, default, allowed values), values parsed from the text a scenario
// or machine file gives. Header-only types (the standard library alone), so a planner plugin
// built outside the project can declare its parameters with them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace taskmatrix::core {

enum class ParamType { kString, kNumber, kInteger, kBool, kStringList };
const char* to_string(ParamType type);

// What a string parameter's value names in the world, so that `taskmatrix validate` and `run`
// check it against every environment of a scenario before anything runs: nothing (kNone), or
// a thing the perceptual model knows (kObject: an environment's object or surface, a debris
// flake, the visitor, an obstacle).
enum class NameKind { kNone, kObject };
using ParamValue = std::variant<std::string, double, std::int64_t, bool, std::vector<std::string>>;

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kString;
  bool required = true;
  ParamValue default_value;          // used when not required and not given
  std::vector<std::string> choices;  // for strings: allowed values (empty: any)
  std::string doc;
  NameKind names = NameKind::kNone;  // for strings: what the value names in the world
};

// Raw parameter text as written in a scenario or machine file, by name.
using RawParams = std::map<std::string, std::string>;

}  // namespace taskmatrix::core
