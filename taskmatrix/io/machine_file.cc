#include "taskmatrix/io/machine_file.h"

#include <map>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::io {

namespace {

std::string raw_text(const YamlNode& node) {
  if (node.is_scalar()) return node.as_string();
  std::string out = "[";
  for (const std::string& s : node.as_strings()) out += (out.size() > 1 ? ", " : "") + s;
  return out + "]";
}

core::RawParams read_params(const std::optional<YamlNode>& node) {
  core::RawParams out;
  if (!node) return out;
  for (const auto& [key, value] : node->entries()) out[key] = raw_text(value);
  return out;
}

core::ParamType param_type(const YamlNode& node) {
  const std::string t = node.as_string();
  if (t == "string") return core::ParamType::kString;
  if (t == "number") return core::ParamType::kNumber;
  if (t == "integer") return core::ParamType::kInteger;
  if (t == "bool") return core::ParamType::kBool;
  if (t == "strings") return core::ParamType::kStringList;
  node.fail("type must be one of string, number, integer, bool, strings");
}

core::MessageType message(const YamlNode& node) {
  try {
    return core::message_type_from_string(node.as_string());
  } catch (const std::invalid_argument& e) {
    node.fail(e.what());
  }
}

core::MachineSpec read(const YamlNode& root) {
  root.expect_keys({"name", "doc", "parameters", "concurrent", "initial", "states", "transitions"});
  core::MachineSpec spec;
  spec.source = root.file();
  spec.name = root.required("name").as_string();
  spec.doc = root.get_string("doc", "");
  if (auto params = root.optional("parameters")) {
    for (const auto& [name, node] : params->entries()) {
      node.expect_keys({"type", "default", "choices", "doc"});
      core::ParamSpec p;
      p.name = name;
      p.type = param_type(node.required("type"));
      if (auto choices = node.optional("choices")) p.choices = choices->as_strings();
      p.doc = node.get_string("doc", "");
      if (auto def = node.optional("default")) {
        p.required = false;
        try {
          p.default_value = core::parse_param(p, raw_text(*def));
        } catch (const std::invalid_argument& e) {
          def->fail(e.what());
        }
      }
      spec.params.push_back(std::move(p));
    }
  }
  if (auto concurrent = root.optional("concurrent")) {
    for (const auto& [name, node] : concurrent->entries()) {
      node.expect_keys({"program", "params", "at_start"});
      core::ConcurrentProgram c;
      c.name = name;
      c.program = node.required("program").as_string();
      c.params = read_params(node.optional("params"));
      if (auto at_start = node.optional("at_start")) c.at_start = at_start->as_bool();
      c.spot = {node.key(), node.line()};
      spec.concurrent.push_back(std::move(c));
    }
  }
  for (const auto& [name, node] : root.required("states").entries()) {
    node.expect_keys({"program", "params", "final", "invariant"});
    core::MachineState s;
    s.name = name;
    if (auto final = node.optional("final")) {
      const std::string kind = final->as_string();
      if (kind != "success" && kind != "failure") final->fail("must be success or failure");
      if (node.has("program")) node.fail("a final state runs no program");
      s.final = true;
      s.success = kind == "success";
    } else {
      s.program = node.required("program").as_string();
      s.params = read_params(node.optional("params"));
      s.invariant = node.get_string("invariant", "");
    }
    s.spot = {node.key(), node.line()};
    spec.states.push_back(std::move(s));
  }
  spec.initial = root.required("initial").as_string();
  if (auto transitions = root.optional("transitions")) {
    for (const YamlNode& node : transitions->items()) {
      node.expect_keys({"from", "on", "to", "start", "stop", "when"});
      core::MachineTransition t;
      t.from = node.required("from").as_string();
      t.on = message(node.required("on"));
      t.to = node.get_string("to", "");
      t.when = node.get_string("when", "");
      if (auto start = node.optional("start")) t.start = start->as_strings();
      if (auto stop = node.optional("stop")) t.stop = stop->as_strings();
      t.spot = {node.key(), node.line()};
      spec.transitions.push_back(std::move(t));
    }
  }
  return spec;
}

}  // namespace

core::MachineSpec load_machine_spec(const std::filesystem::path& file) {
  return read(YamlNode::load_file(file));
}

void load_and_register_machine(const std::filesystem::path& file, core::ProgramRegistry& registry) {
  register_machine_node(YamlNode::load_file(file), registry);
}

std::string register_machine_node(const YamlNode& root, core::ProgramRegistry& registry) {
  const core::MachineSpec spec = read(root);
  try {
    core::register_machine(spec, registry);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    core::SourceSpot at{root.key(), root.line()};
    auto names = [&](const std::string& name) {
      return what.find("state '" + name + "'") != std::string::npos ||
             what.find("program '" + name + "'") != std::string::npos;
    };
    for (const core::ConcurrentProgram& c : spec.concurrent) {
      if (names(c.name)) at = c.spot;
    }
    for (const core::MachineState& s : spec.states) {
      if (names(s.name)) at = s.spot;
    }
    for (size_t k = 0; k < spec.transitions.size(); ++k) {
      if (what.find("transition " + std::to_string(k) + " ") != std::string::npos) {
        at = spec.transitions[k].spot;
      }
    }
    throw core::InputError(root.file(), at.key, what, at.line);
  }
  return spec.name;
}

}  // namespace taskmatrix::io
