#include "harness/scenario.h"

#include <algorithm>

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::harness {

namespace {

// Scalars as text, lists as "[a, b]", for the program's own parameter parsing.
core::RawParams read_params(const std::optional<io::YamlNode>& node) {
  core::RawParams out;
  if (!node) return out;
  for (const auto& [key, value] : node->entries()) {
    if (value.is_scalar()) {
      out[key] = value.as_string();
    } else {
      std::string list = "[";
      for (const std::string& item : value.as_strings())
        list += (list.size() > 1 ? ", " : "") + item;
      out[key] = list + "]";
    }
  }
  return out;
}

ProgramCall read_call(const io::YamlNode& node, const core::ProgramRegistry& registry,
                      const io::YamlNode& program_node,
                      const std::optional<io::YamlNode>& params_node) {
  ProgramCall call;
  call.program = program_node.as_string();
  if (!registry.find(call.program)) {
    std::string known;
    for (const std::string& n : registry.names()) known += (known.empty() ? "" : ", ") + n;
    program_node.fail("unknown program '" + call.program + "' (known: " + known + ")");
  }
  call.params = read_params(params_node);
  try {
    core::check_params(registry.find(call.program)->params, call.params);
  } catch (const std::invalid_argument& e) {
    (params_node ? *params_node : node).fail(e.what());
  }
  return call;
}

std::vector<std::string> read_names(const io::YamlNode& node, const std::vector<std::string>& known,
                                    const char* what) {
  std::vector<std::string> names = node.as_strings();
  if (names.empty()) node.fail(std::string("needs at least one ") + what);
  for (const std::string& n : names) {
    if (std::find(known.begin(), known.end(), n) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      node.fail("unknown " + std::string(what) + " '" + n + "' (known: " + list + ")");
    }
  }
  return names;
}

}  // namespace

Scenario load_scenario(const std::filesystem::path& file, const ModelCatalog& catalog,
                       const core::ProgramRegistry& registry) {
  const io::YamlNode root = io::YamlNode::load_file(file);
  root.expect_keys({"name", "doc", "program", "params", "setup", "robots", "environments",
                    "perception", "obstacles", "layout_seed", "seed", "trials", "visitor",
                    "plan_time_limit_s", "time_limit_s", "success"});
  Scenario s;
  s.file = file;
  s.name = root.get_string("name", file.stem().string());
  s.doc = root.get_string("doc", "");
  s.run = read_call(root, registry, root.required("program"), root.optional("params"));
  if (auto setup = root.optional("setup")) {
    for (const io::YamlNode& step : setup->items()) {
      step.expect_keys({"program", "params"});
      s.setup.push_back(
          read_call(step, registry, step.required("program"), step.optional("params")));
    }
  }
  s.robots = read_names(root.required("robots"), catalog.robots(), "robot");
  s.environments = read_names(root.required("environments"), catalog.environments(), "environment");
  if (auto p = root.optional("perception")) {
    s.perception = p->as_string();
    if (s.perception != "ground_truth" && s.perception != "sensor") {
      p->fail("must be ground_truth or sensor, not '" + s.perception + "'");
    }
  }
  if (auto o = root.optional("obstacles")) {
    o->expect_keys({"count"});
    const io::YamlNode count = o->required("count");
    s.obstacles = count.as_int();
    if (s.obstacles < 0) count.fail("must be 0 or more");
  }
  if (auto seed = root.optional("layout_seed")) {
    const int v = seed->as_int();
    if (v < 0) seed->fail("must be 0 or more");
    s.layout_seed = static_cast<std::uint64_t>(v);
  }
  if (auto seed = root.optional("seed")) {
    const int v = seed->as_int();
    if (v < 1) seed->fail("must be 1 or more");
    s.seed = static_cast<std::uint32_t>(v);
  }
  if (auto trials = root.optional("trials")) {
    s.trials = trials->as_int();
    if (s.trials < 1) trials->fail("must be 1 or more");
  }
  if (auto visitor = root.optional("visitor")) {
    visitor->expect_keys({"walk_speed"});
    if (auto speed = visitor->optional("walk_speed")) {
      s.visitor_speed_mps = speed->as_double();
      if (s.visitor_speed_mps < 0 || s.visitor_speed_mps > 3) speed->fail("must be in [0, 3] m/s");
    }
  }
  if (auto t = root.optional("plan_time_limit_s")) s.plan_time_limit_s = t->as_positive_double();
  if (auto t = root.optional("time_limit_s")) s.time_limit_s = t->as_positive_double();
  if (auto success = root.optional("success")) {
    s.success = success->as_string();
    try {
      core::parse_condition(s.success);
    } catch (const std::invalid_argument& e) {
      success->fail(e.what());
    }
  }
  return s;
}

}  // namespace taskmatrix::harness
