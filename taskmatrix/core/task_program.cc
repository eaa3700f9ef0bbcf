#include "taskmatrix/core/task_program.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace taskmatrix::core {

const char* to_string(ParamType type) {
  switch (type) {
    case ParamType::kString:
      return "string";
    case ParamType::kNumber:
      return "number";
    case ParamType::kInteger:
      return "integer";
    case ParamType::kBool:
      return "bool";
    case ParamType::kStringList:
      return "list of strings";
  }
  return "?";
}

const ParamValue& Params::at(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw std::invalid_argument("no parameter '" + name + "'");
  return it->second;
}
const std::string& Params::text(const std::string& name) const {
  return std::get<std::string>(at(name));
}
double Params::number(const std::string& name) const { return std::get<double>(at(name)); }
std::int64_t Params::integer(const std::string& name) const {
  return std::get<std::int64_t>(at(name));
}
bool Params::flag(const std::string& name) const { return std::get<bool>(at(name)); }
const std::vector<std::string>& Params::list(const std::string& name) const {
  return std::get<std::vector<std::string>>(at(name));
}

namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

ParamValue parse_param(const ParamSpec& spec, const std::string& raw) {
  const std::string text = trim(raw);
  auto bad = [&](const std::string& why) {
    return std::invalid_argument("'" + text + "' is not " + why);
  };
  switch (spec.type) {
    case ParamType::kString: {
      if (text.empty()) throw bad("a non-empty string");
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end()) {
        std::string allowed;
        for (const std::string& c : spec.choices) allowed += (allowed.empty() ? "" : ", ") + c;
        throw bad("one of: " + allowed);
      }
      return text;
    }
    case ParamType::kNumber: {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
        throw bad("a finite number");
      return v;
    }
    case ParamType::kInteger: {
      char* end = nullptr;
      errno = 0;
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || errno != 0) throw bad("an integer");
      return static_cast<std::int64_t>(v);
    }
    case ParamType::kBool:
      if (text == "true") return true;
      if (text == "false") return false;
      throw bad("true or false");
    case ParamType::kStringList: {
      // "[a, b]" or "a, b"
      std::string body = text;
      if (!body.empty() && body.front() == '[') {
        if (body.back() != ']') throw bad("a list [a, b, ...]");
        body = body.substr(1, body.size() - 2);
      }
      std::vector<std::string> items;
      size_t start = 0;
      while (start <= body.size()) {
        const size_t comma = body.find(',', start);
        const std::string item = trim(body.substr(start, comma - start));
        if (!item.empty()) items.push_back(item);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      if (items.empty()) throw bad("a non-empty list");
      return items;
    }
  }
  throw bad("valid");
}

Params check_params(const std::vector<ParamSpec>& specs, const RawParams& raw) {
  std::map<std::string, ParamValue> values;
  for (const auto& [name, text] : raw) {
    const auto spec = std::find_if(specs.begin(), specs.end(),
                                   [&](const ParamSpec& s) { return s.name == name; });
    if (spec == specs.end()) {
      std::string known;
      for (const ParamSpec& s : specs) known += (known.empty() ? "" : ", ") + s.name;
      throw std::invalid_argument("parameter '" + name +
                                  "' is unknown (known: " + (known.empty() ? "none" : known) + ")");
    }
    try {
      values[name] = parse_param(*spec, text);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("parameter '" + name + "': " + e.what());
    }
  }
  for (const ParamSpec& s : specs) {
    if (values.count(s.name)) continue;
    if (s.required) {
      throw std::invalid_argument("parameter '" + s.name + "' (" + to_string(s.type) +
                                  ") is required");
    }
    values[s.name] = s.default_value;
  }
  return Params(std::move(values));
}

const char* to_string(MessageType type) {
  switch (type) {
    case MessageType::kStarted:
      return "started";
    case MessageType::kPlanningStarted:
      return "planning_started";
    case MessageType::kPlanningEnded:
      return "planning_ended";
    case MessageType::kCompleted:
      return "completed";
    case MessageType::kFailed:
      return "failed";
    case MessageType::kHalted:
      return "halted";
  }
  return "?";
}

MessageType message_type_from_string(const std::string& name) {
  for (MessageType t :
       {MessageType::kStarted, MessageType::kPlanningStarted, MessageType::kPlanningEnded,
        MessageType::kCompleted, MessageType::kFailed, MessageType::kHalted}) {
    if (name == to_string(t)) return t;
  }
  throw std::invalid_argument(
      "'" + name +
      "' is not a message (started, planning_started, planning_ended, completed, failed, halted)");
}

std::string path_step(const std::string& program, const std::string& state) {
  return state == program || state.empty() ? program : program + "(" + state + ")";
}

void TaskProgram::halt(ProgramContext& ctx) {
  const std::vector<std::string> mine = chains(ctx.skills());
  if (!mine.empty()) ctx.skills().command(mine, ctx.skills().clamped_configuration(mine));
}

void ProgramRegistry::add(ProgramType type) {
  if (types_.count(type.name)) {
    throw std::invalid_argument("program '" + type.name + "' is registered twice");
  }
  std::string name = type.name;
  types_.emplace(std::move(name), std::move(type));
}

const ProgramType* ProgramRegistry::find(const std::string& name) const {
  const auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> ProgramRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

std::unique_ptr<TaskProgram> ProgramRegistry::instantiate(const std::string& name,
                                                          const RawParams& raw) const {
  const ProgramType* type = find(name);
  if (!type) throw std::invalid_argument("unknown program '" + name + "'");
  try {
    return type->make(check_params(type->params, raw));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("program '" + name + "': " + e.what());
  }
}

}  // namespace taskmatrix::core
