#include "harness/scenario/scenario.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <tuple>

#include "harness/scenario/planner_plugins.h"
#include "taskmatrix/core/conditions.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/io/machine_file.h"
#include "taskmatrix/io/text_file.h"
#include "taskmatrix/io/yaml_reader.h"

namespace taskmatrix::harness {

const std::vector<std::string>& execution_modes() {
  static const std::vector<std::string> modes = {"physics", "kinematic", "physics_unpruned"};
  return modes;
}

bool is_execution_mode(const std::string& name) {
  const std::vector<std::string>& modes = execution_modes();
  return std::find(modes.begin(), modes.end(), name) != modes.end();
}

std::string execution_modes_text() {
  const std::vector<std::string>& modes = execution_modes();
  std::string text;
  for (size_t i = 0; i < modes.size(); ++i) {
    if (i > 0) text += i + 1 == modes.size() ? " or " : ", ";
    text += modes[i];
  }
  return text;
}

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

// The names `call` gives to things in the world (core::names_used), with where the scenario
// writes each: its parameter under `prefix` ("" or "setup[k]."), else the machine file's state
// or transition, else the program's key.
// `defaults_node`: the inline machine's `parameters:`, where its defaults are written.
void add_names(Scenario& s, const core::ProgramRegistry& registry, const ProgramCall& call,
               const std::string& prefix, const io::YamlNode& program_node,
               const std::optional<io::YamlNode>& params_node,
               const std::optional<io::YamlNode>& defaults_node = std::nullopt) {
  std::vector<core::NameUse> uses;
  try {
    uses = core::names_used(registry, call.program, call.params);
  } catch (const std::invalid_argument& e) {
    // A value a machine passes on that the program it calls refuses.
    (params_node ? *params_node : program_node).fail(e.what());
  }
  for (const core::NameUse& u : uses) {
    NameRef r{u.name, s.file, prefix + "program", program_node.line(), u.path};
    if (!u.param.empty()) {
      // Given in the call's params, or a default written in the inline machine's parameters.
      const std::optional<io::YamlNode>& in = u.defaulted ? defaults_node : params_node;
      const std::optional<io::YamlNode> written = in ? in->optional(u.param) : std::nullopt;
      r.key = written ? written->key() : prefix + "params." + u.param;
      if (written) r.line = written->line();
    } else if (!u.file.empty() && !u.spot.key.empty()) {
      r = {u.name, u.file, u.spot.key, u.spot.line, u.path};
    }
    if (u.defaulted) {
      r.use += u.param.empty() ? " (its default)" : " (the default of '" + u.param + "')";
    }
    s.names.push_back(std::move(r));
  }
}

// `known`: the names allowed; null: any safe name (a list something else replaces).
std::vector<std::string> read_names(const io::YamlNode& node, const std::vector<std::string>* known,
                                    const char* what) {
  std::vector<std::string> names = node.as_strings();
  if (names.empty()) node.fail(std::string("needs at least one ") + what);
  for (const std::string& n : names) {
    if (const std::string bad = unsafe_name_reason(what, n); !bad.empty()) node.fail(bad);
    if (known && std::find(known->begin(), known->end(), n) == known->end()) {
      std::string list;
      for (const std::string& k : *known) list += (list.empty() ? "" : ", ") + k;
      node.fail("unknown " + std::string(what) + " '" + n + "' (known: " + list + ")");
    }
  }
  return names;
}

// `base`: the folder of the file that lists the planners (plugin paths are relative to it).
std::vector<PlannerConfig> read_planners(const io::YamlNode& node,
                                         const std::filesystem::path& base) {
  std::vector<PlannerConfig> out;
  for (const io::YamlNode& item : node.items()) {
    PlannerConfig p;
    if (item.is_scalar()) {
      p.spec.name = item.as_string();
    } else {
      item.expect_keys({"name", "label", "params", "plugin"});
      p.spec.name = item.required("name").as_string();
      if (auto plugin = item.optional("plugin")) {
        std::filesystem::path library = plugin->as_string();
        if (library.is_relative()) library = base / library;
        std::vector<std::string> names;
        try {
          names = load_planner_plugin(library);
        } catch (const std::runtime_error& e) {
          plugin->fail(e.what());
        }
        if (std::find(names.begin(), names.end(), p.spec.name) == names.end()) {
          std::string list;
          for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
          item.required("name").fail("planner plugin " + library.string() + " registers no '" +
                                     p.spec.name + "' (it registers: " + list + ")");
        }
      }
      if (auto params = item.optional("params")) {
        for (const auto& [key, value] : params->entries()) p.spec.params[key] = value.as_string();
      }
    }
    p.label = item.is_scalar() ? p.spec.name : item.get_string("label", p.spec.name);
    if (const std::string bad = unsafe_name_reason("planner label", p.label); !bad.empty()) {
      item.fail(bad);
    }
    if (const std::string bad = check_planner(p.spec); !bad.empty()) {
      if (item.is_scalar() || !item.has("params") ||
          core::planner_registry().find(p.spec.name) == nullptr) {
        item.fail(bad);
      }
      item.required("params").fail(bad);
    }
    for (const PlannerConfig& q : out) {
      if (q.label == p.label) item.fail("planner label '" + p.label + "' appears twice");
    }
    out.push_back(std::move(p));
  }
  if (out.empty()) node.fail("needs at least one planner");
  return out;
}

std::pair<double, double> read_range(const io::YamlNode& node) {
  const std::vector<double> v = node.as_doubles();
  if (v.size() != 2 || !(v[0] > 0) || !(v[1] >= v[0])) {
    node.fail("must be [min, max] with 0 < min <= max (metres)");
  }
  return {v[0], v[1]};
}

core::ObstacleOptions read_obstacles(const io::YamlNode& o, KeyLines& lines) {
  o.expect_keys({"count", "regions", "shapes", "footprint_m", "half_height_m", "near", "path",
                 "overhead", "floor"});
  core::ObstacleOptions out;
  read_targeted_obstacles(o, out, lines);
  const io::YamlNode count = out.targeted.empty() || o.has("count") ? o.required("count") : o;
  out.count = count.is_map() ? 0 : count.as_int();
  if (out.count < 0) count.fail("must be 0 or more");
  if (auto regions = o.optional("regions")) {
    out.regions = regions->as_strings();
    if (out.regions.empty()) regions->fail("needs at least one region name");
  }
  if (auto shapes = o.optional("shapes")) {
    out.shapes.clear();
    for (const std::string& name : shapes->as_strings()) {
      if (name == "box") {
        out.shapes.push_back(core::ObstacleShape::kBox);
      } else if (name == "cylinder") {
        out.shapes.push_back(core::ObstacleShape::kCylinder);
      } else if (name == "sphere") {
        out.shapes.push_back(core::ObstacleShape::kSphere);
      } else {
        shapes->fail("unknown shape '" + name + "' (known: box, cylinder, sphere)");
      }
    }
    if (out.shapes.empty()) shapes->fail("needs at least one shape");
  }
  if (auto f = o.optional("footprint_m")) {
    std::tie(out.footprint_min_m, out.footprint_max_m) = read_range(*f);
  }
  if (auto h = o.optional("half_height_m")) {
    std::tie(out.half_height_min_m, out.half_height_max_m) = read_range(*h);
  }
  return out;
}

std::uint64_t read_layout_seed(const io::YamlNode& node) { return node.as_uint64(); }

std::uint32_t read_seed(const io::YamlNode& node) {
  const int v = node.as_int();
  if (v < 1) node.fail("must be 1 or more");
  return static_cast<std::uint32_t>(v);
}

std::string read_planner_budget(const io::YamlNode& node) {
  const std::string v = node.as_string();
  if (v != "iterations" && v != "time") node.fail("must be iterations or time, not '" + v + "'");
  return v;
}

unsigned read_plan_iterations(const io::YamlNode& node) {
  const int v = node.as_int();
  if (v < 1 || v > 100000000) node.fail("must be in 1..100000000");
  return static_cast<unsigned>(v);
}

// Beyond a day OMPL's deadline arithmetic overflows (every plan would time out at once).
double read_plan_time_limit(const io::YamlNode& node) {
  const double v = node.as_positive_double();
  if (v > 86400) node.fail("must be at most 86400 s (a day)");
  return v;
}

double read_wall_limit(const io::YamlNode& node) {
  const double v = node.as_positive_double();
  if (v > 86400) node.fail("must be at most 86400 s (a day)");
  return v;
}

std::string read_execution(const io::YamlNode& node) {
  const std::string v = node.as_string();
  if (!is_execution_mode(v)) node.fail("must be " + execution_modes_text() + ", not '" + v + "'");
  return v;
}

int read_trials(const io::YamlNode& node) {
  const int v = node.as_int();
  if (v < 1 || v > 100000) node.fail("must be in 1..100000");
  return v;
}

}  // namespace

std::string check_planner(const core::PlannerSpec& spec) {
  register_builtin_planners();
  return core::planner_registry().check(spec.name, spec.params);
}

Scenario load_scenario(const std::filesystem::path& file, const ModelCatalog& catalog,
                       core::ProgramRegistry& registry, ReplacedLists replaced) {
  const io::YamlNode root = io::YamlNode::load_file(file);
  root.expect_keys({"name",
                    "doc",
                    "program",
                    "machine",
                    "params",
                    "setup",
                    "robots",
                    "environments",
                    "perception",
                    "obstacles",
                    "planners",
                    "layout_seed",
                    "seed",
                    "trials",
                    "visitor",
                    "planner_budget",
                    "plan_iterations",
                    "plan_time_limit_s",
                    "time_limit_s",
                    "wall_limit_s",
                    "success",
                    "execution",
                    "objects",
                    "surfaces",
                    "robot_start"});
  Scenario s;
  s.file = file;
  s.file_text = io::read_text_file(file);
  s.name = root.get_string("name", file.stem().string());
  if (const std::string bad = unsafe_name_reason("scenario", s.name); !bad.empty()) {
    (root.has("name") ? root.required("name") : root).fail(bad);
  }
  s.doc = root.get_string("doc", "");
  // The inline machine's name and where its parameters' defaults are written.
  std::string inline_machine;
  std::optional<io::YamlNode> inline_defaults;
  if (auto machine = root.optional("machine")) {
    const std::string name = machine->get_string("name", "");
    if (!name.empty() && registry.find(name)) {
      machine->required("name").fail("a program named '" + name + "' already exists");
    }
    inline_machine = io::register_machine_node(*machine, registry);
    inline_defaults = machine->optional("parameters");
    if (root.has("program") && root.required("program").as_string() != inline_machine) {
      root.required("program").fail("names '" + root.required("program").as_string() +
                                    "' but the inline machine is '" + inline_machine + "'");
    }
    const io::YamlNode program =
        root.has("program") ? root.required("program") : machine->required("name");
    s.run = read_call(root, registry, program, root.optional("params"));
    add_names(s, registry, s.run, "", program, root.optional("params"), inline_defaults);
  } else {
    s.run = read_call(root, registry, root.required("program"), root.optional("params"));
    add_names(s, registry, s.run, "", root.required("program"), root.optional("params"));
  }
  if (auto setup = root.optional("setup")) {
    size_t k = 0;
    for (const io::YamlNode& step : setup->items()) {
      step.expect_keys({"program", "params"});
      s.setup.push_back(
          read_call(step, registry, step.required("program"), step.optional("params")));
      add_names(s, registry, s.setup.back(), "setup[" + std::to_string(k++) + "].",
                step.required("program"), step.optional("params"),
                s.setup.back().program == inline_machine ? inline_defaults : std::nullopt);
    }
  }
  const std::vector<std::string> robots = catalog.robots(), environments = catalog.environments();
  s.robots = read_names(root.required("robots"), replaced.robots ? nullptr : &robots, "robot");
  s.environments = read_names(root.required("environments"),
                              replaced.environments ? nullptr : &environments, "environment");
  if (auto p = root.optional("perception")) {
    s.perception = p->as_string();
    if (s.perception != "ground_truth" && s.perception != "sensor") {
      p->fail("must be ground_truth or sensor, not '" + s.perception + "'");
    }
  }
  if (auto e = root.optional("execution")) s.execution = read_execution(*e);
  if (auto o = root.optional("obstacles")) s.obstacles = read_obstacles(*o, s.key_lines);
  s.variation = read_variation(root, s.key_lines);
  s.variation_file = file;
  if (auto p = root.optional("planners")) s.planners = read_planners(*p, file.parent_path());
  if (auto seed = root.optional("layout_seed")) s.layout_seed = read_layout_seed(*seed);
  if (auto seed = root.optional("seed")) s.seed = read_seed(*seed);
  if (auto trials = root.optional("trials")) s.trials = read_trials(*trials);
  if (auto visitor = root.optional("visitor")) {
    visitor->expect_keys({"walk_speed"});
    if (auto speed = visitor->optional("walk_speed")) {
      s.visitor_speed_mps = speed->as_double();
      if (s.visitor_speed_mps < 0 || s.visitor_speed_mps > 3) speed->fail("must be in [0, 3] m/s");
    }
  }
  if (auto b = root.optional("planner_budget")) s.planner_budget = read_planner_budget(*b);
  if (auto n = root.optional("plan_iterations")) s.plan_iterations = read_plan_iterations(*n);
  if (auto t = root.optional("plan_time_limit_s")) s.plan_time_limit_s = read_plan_time_limit(*t);
  if (auto t = root.optional("time_limit_s")) s.time_limit_s = t->as_positive_double();
  if (auto t = root.optional("wall_limit_s")) s.wall_limit_s = read_wall_limit(*t);
  if (auto success = root.optional("success")) {
    s.success = success->as_string();
    try {
      for (const std::string& name : core::condition_object_names(s.success)) {
        s.names.push_back({name, file, "success", success->line(), "success: " + s.success});
      }
    } catch (const std::invalid_argument& e) {
      success->fail(e.what());
    }
  }
  return s;
}

void check_names(const Scenario& s, const core::EnvironmentSpec& environment) {
  std::set<std::string> objects;
  for (const auto& [name, spec] : environment.objects) {
    for (const std::string& body : spec.bodies)
      objects.insert(core::perceived_id(name, spec, body));
  }
  if (!environment.visitor.body.empty()) objects.insert(core::kVisitorId);
  std::string known;
  for (const std::string& n : objects) known += (known.empty() ? "" : ", ") + n;
  // The obstacles as the perceptual model names them.
  for (int k = 0; k < environment.obstacle_slots; ++k) objects.insert(core::obstacle_id(k));
  if (environment.obstacle_slots > 0) {
    known +=
        ", " + core::obstacle_id(0) + " to " + core::obstacle_id(environment.obstacle_slots - 1);
  }
  for (const NameRef& r : s.names) {
    if (objects.count(r.name)) continue;
    throw core::InputError(r.file.string(), r.key,
                           "no object '" + r.name + "' in environment '" + environment.name +
                               "' (used by " + r.use + "; it knows: " + known + ")",
                           r.line);
  }
}

RunPlan load_run_plan(const std::filesystem::path& file, const ModelCatalog& catalog,
                      core::ProgramRegistry& registry, ReplacedLists replaced) {
  RunPlan plan;
  plan.file = file;
  const io::YamlNode root = io::YamlNode::load_file(file);
  if (!root.has("suite")) {
    plan.scenarios.push_back(load_scenario(file, catalog, registry, replaced));
    plan.name = plan.scenarios[0].name;
    plan.doc = plan.scenarios[0].doc;
    return plan;
  }
  root.expect_keys({"suite", "doc", "scenarios", "trials", "layout_seed", "seed", "planners",
                    "robots", "environments", "planner_budget", "plan_iterations",
                    "plan_time_limit_s", "wall_limit_s", "execution", "objects", "surfaces",
                    "robot_start"});
  plan.suite = true;
  plan.text = io::read_text_file(file);
  plan.name = root.required("suite").as_string();
  if (const std::string bad = unsafe_name_reason("suite", plan.name); !bad.empty()) {
    root.required("suite").fail(bad);
  }
  plan.doc = root.get_string("doc", "");
  const io::YamlNode list = root.required("scenarios");
  const ReplacedLists by_suite{replaced.robots || root.has("robots"),
                               replaced.environments || root.has("environments")};
  for (const io::YamlNode& item : list.items()) {
    std::filesystem::path included = item.as_string();
    if (included.is_relative()) included = file.parent_path() / included;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(included, ec)) {
      item.fail("no scenario file '" + included.string() + "'");
    }
    Scenario s = load_scenario(included, catalog, registry, by_suite);
    for (const Scenario& other : plan.scenarios) {
      if (other.name == s.name) item.fail("two scenarios are named '" + s.name + "'");
    }
    plan.scenarios.push_back(std::move(s));
  }
  if (plan.scenarios.empty()) list.fail("needs at least one scenario");
  const std::vector<std::string> robots = catalog.robots(), environments = catalog.environments();
  for (Scenario& s : plan.scenarios) {
    if (auto n = root.optional("trials")) s.trials = read_trials(*n);
    if (auto n = root.optional("layout_seed")) s.layout_seed = read_layout_seed(*n);
    if (auto n = root.optional("seed")) s.seed = read_seed(*n);
    if (auto n = root.optional("planners")) s.planners = read_planners(*n, file.parent_path());
    if (auto n = root.optional("robots")) {
      s.robots = read_names(*n, replaced.robots ? nullptr : &robots, "robot");
    }
    if (auto n = root.optional("environments")) {
      s.environments =
          read_names(*n, replaced.environments ? nullptr : &environments, "environment");
    }
    if (auto n = root.optional("planner_budget")) s.planner_budget = read_planner_budget(*n);
    if (auto n = root.optional("plan_iterations")) s.plan_iterations = read_plan_iterations(*n);
    if (auto n = root.optional("plan_time_limit_s")) s.plan_time_limit_s = read_plan_time_limit(*n);
    if (auto n = root.optional("wall_limit_s")) s.wall_limit_s = read_wall_limit(*n);
    if (auto n = root.optional("execution")) s.execution = read_execution(*n);
  }
  // Variation keys of the suite replace each scenario's.
  KeyLines suite_lines;
  const core::VariationOptions variation = read_variation(root, suite_lines);
  if (!variation.empty()) {
    for (Scenario& s : plan.scenarios) {
      s.variation = variation;
      for (auto it = s.key_lines.begin(); it != s.key_lines.end();) {
        const bool varied = it->first.rfind("objects", 0) == 0 ||
                            it->first.rfind("surfaces", 0) == 0 ||
                            it->first.rfind("robot_start", 0) == 0;
        it = varied ? s.key_lines.erase(it) : std::next(it);
      }
      s.key_lines.insert(suite_lines.begin(), suite_lines.end());
      s.variation_file = file;
    }
  }
  return plan;
}

ReplacedLists replaced_by(const RunOverrides& overrides) {
  return {!overrides.robots.empty(), !overrides.environments.empty()};
}

void apply_overrides(RunPlan& plan, const RunOverrides& overrides) {
  if (!overrides.execution.empty() && !is_execution_mode(overrides.execution)) {
    throw core::InputError(
        "--execution", "",
        "must be " + execution_modes_text() + ", not '" + overrides.execution + "'");
  }
  std::vector<PlannerConfig> planners;
  for (const std::string& name : overrides.planners) {
    PlannerConfig p{name, {}};
    p.spec.name = name;
    if (const std::string bad = check_planner(p.spec); !bad.empty()) {
      throw core::InputError("--planners", "", bad);
    }
    for (const PlannerConfig& q : planners) {
      if (q.label == name) throw core::InputError("--planners", "", name + " appears twice");
    }
    planners.push_back(std::move(p));
  }
  for (Scenario& s : plan.scenarios) {
    if (overrides.trials > 0) s.trials = overrides.trials;
    if (overrides.seed > 0) s.seed = overrides.seed;
    if (!planners.empty()) s.planners = planners;
    if (s.layout_seed > UINT64_MAX - static_cast<std::uint64_t>(s.trials - 1)) {
      throw core::InputError(s.file.string(), "layout_seed",
                             "layout_seed + trials - 1 must stay within 2^64 - 1");
    }
    if (!overrides.execution.empty()) s.execution = overrides.execution;
    if (!overrides.robots.empty()) s.robots = overrides.robots;
    if (!overrides.environments.empty()) s.environments = overrides.environments;
    if (static_cast<std::uint64_t>(s.seed) + static_cast<std::uint64_t>(s.trials) - 1 >
        0xffffffffULL) {
      throw core::InputError("--seed", "",
                             "seed + trials - 1 must stay within 4294967295 (planner seeds of "
                             "scenario " +
                                 s.name + ")");
    }
  }
}

}  // namespace taskmatrix::harness
