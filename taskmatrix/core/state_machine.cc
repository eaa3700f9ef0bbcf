#include "taskmatrix/core/state_machine.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace taskmatrix::core {

namespace {

const MachineState* find_state(const MachineSpec& spec, const std::string& name) {
  for (const MachineState& s : spec.states) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const ConcurrentProgram* find_concurrent(const MachineSpec& spec, const std::string& name) {
  for (const ConcurrentProgram& c : spec.concurrent) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string param_text(const ParamValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (const auto* d = std::get_if<double>(&v)) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", *d);
    return buf;
  }
  if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  std::string out = "[";
  for (const std::string& item : std::get<std::vector<std::string>>(v))
    out += (out.size() > 1 ? ", " : "") + item;
  return out + "]";
}

// Replaces "$name" values with the machine's parameter values.
RawParams substitute(const RawParams& raw, const Params& machine_params) {
  RawParams out;
  for (const auto& [key, value] : raw) {
    if (!value.empty() && value.front() == '$') {
      out[key] = param_text(machine_params.values().at(value.substr(1)));
    } else {
      out[key] = value;
    }
  }
  return out;
}

// Replaces "$name" references inside a condition's text.
std::string substitute_condition(const std::string& text, const Params& machine_params) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    if (text[i] != '$') {
      out += text[i++];
      continue;
    }
    size_t end = i + 1;
    while (end < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_')) {
      ++end;
    }
    out += param_text(machine_params.values().at(text.substr(i + 1, end - i - 1)));
    i = end;
  }
  return out;
}

// Checks a condition's text and its "$x" references (which must name string parameters).
void check_condition(const MachineSpec& spec, const std::string& text, const std::string& where) {
  std::map<std::string, ParamValue> placeholders;
  for (const ParamSpec& p : spec.params) placeholders[p.name] = std::string("x");
  for (size_t i = text.find('$'); i != std::string::npos; i = text.find('$', i + 1)) {
    size_t end = i + 1;
    while (end < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_')) {
      ++end;
    }
    const std::string ref = text.substr(i + 1, end - i - 1);
    if (!placeholders.count(ref)) {
      throw std::invalid_argument(where + ": condition '" + text + "' refers to $" + ref +
                                  ", which machine '" + spec.name + "' does not declare");
    }
  }
  try {
    parse_condition(substitute_condition(text, Params(placeholders)));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
}

// Checks a program's parameters as far as they are known before the machine's own are:
// names, literal values, and "$x" references with compatible types.
void check_program_params(const MachineSpec& spec, const ProgramRegistry& registry,
                          const std::string& program, const RawParams& params,
                          const std::string& where) {
  const ProgramType* type = registry.find(program);
  if (!type) throw std::invalid_argument(where + ": unknown program '" + program + "'");
  RawParams literal;
  for (const auto& [key, value] : params) {
    const auto ps = std::find_if(type->params.begin(), type->params.end(),
                                 [&](const ParamSpec& p) { return p.name == key; });
    if (ps == type->params.end()) {
      throw std::invalid_argument(where + ": program '" + program + "' has no parameter '" + key +
                                  "'");
    }
    if (!value.empty() && value.front() == '$') {
      const std::string ref = value.substr(1);
      const auto mp = std::find_if(spec.params.begin(), spec.params.end(),
                                   [&](const ParamSpec& p) { return p.name == ref; });
      if (mp == spec.params.end()) {
        throw std::invalid_argument(where + ": parameter '" + key + "' refers to $" + ref +
                                    ", which machine '" + spec.name + "' does not declare");
      }
      if (mp->type != ps->type) {
        throw std::invalid_argument(where + ": parameter '" + key + "' is a " +
                                    to_string(ps->type) + " but $" + ref + " is a " +
                                    to_string(mp->type));
      }
      continue;
    }
    literal[key] = value;
  }
  // Literal values and required names, with references standing in as given.
  for (const ParamSpec& p : type->params) {
    if (literal.count(p.name)) {
      try {
        parse_param(p, literal.at(p.name));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + ": parameter '" + p.name + "': " + e.what());
      }
    } else if (p.required && !params.count(p.name)) {
      throw std::invalid_argument(where + ": program '" + program + "' needs parameter '" + p.name +
                                  "' (" + to_string(p.type) + ")");
    }
  }
}

class StateMachineProgram final : public TaskProgram {
 public:
  StateMachineProgram(MachineSpec spec, Params params)
      : spec_(std::move(spec)), params_(std::move(params)) {
    // Guards and invariants, parsed once with this instance's parameters.
    for (const MachineTransition& t : spec_.transitions) {
      guards_.push_back(t.when.empty() ? nullptr
                                       : parse_condition(substitute_condition(t.when, params_)));
    }
    for (const MachineState& st : spec_.states) {
      if (!st.invariant.empty()) {
        invariants_[st.name] = parse_condition(substitute_condition(st.invariant, params_));
      }
    }
  }

  std::vector<std::string> chains(const Skillset&) const override { return {}; }

  void start(ProgramContext& ctx) override {
    for (const ConcurrentProgram& c : spec_.concurrent) {
      if (c.at_start) start_concurrent(ctx, c);
    }
    enter(ctx, spec_.initial);
  }

  ProgramState step(ProgramContext& ctx) override {
    std::vector<Message> inbox = ctx.take_inbox();
    if (!done_ && invariant_ && current_child_ >= 0 && !invariant_->holds(ctx.world())) {
      // The state's program is stopped and the state fails as if the program had failed.
      const int child = current_child_;
      current_child_ = -1;
      ctx.halt_child(child);
      for (Message& m : ctx.take_inbox()) inbox.push_back(std::move(m));
      // The child's own messages (its "halted") are superseded by this failure.
      Message failed;
      failed.time = ctx.time();
      failed.sender = kInvariantSender;
      failed.type = MessageType::kFailed;
      failed.failure = Failure(FailureCode::kInvariantFalse,
                               invariant_->explain(ctx.world()) + " (state " + current_ + ")");
      inbox.push_back(failed);
    }
    for (const Message& m : inbox) {
      if (done_) break;
      std::string source;
      if (m.sender == current_child_) source = current_;
      if (m.sender == kInvariantSender) source = current_;
      for (const auto& [name, id] : concurrent_ids_) {
        if (id == m.sender) source = name;
      }
      if (source.empty()) continue;  // an old child's late message
      // Where a failure happened: this state (or concurrent program) and the path inside it.
      const std::string inner = m.failure ? m.failure->path : "";
      const std::string where = step_label(source) + (inner.empty() ? "" : " > " + inner);
      const MachineTransition* t = nullptr;
      std::string guards_false;
      for (size_t k = 0; k < spec_.transitions.size(); ++k) {
        const MachineTransition& tr = spec_.transitions[k];
        if (tr.from != source || tr.on != m.type) continue;
        if (const ConditionPtr& guard = guards_[k]) {
          if (!guard->holds(ctx.world())) {
            guards_false += (guards_false.empty() ? "" : ", ") + guard->describe();
            continue;
          }
        }
        t = &tr;
        break;
      }
      const bool terminal = m.type == MessageType::kCompleted || m.type == MessageType::kFailed ||
                            m.type == MessageType::kHalted;
      if (!t) {
        if (source == current_ && terminal) {
          // No transition for a failure: the machine fails with the state's reason.
          current_child_ = -1;
          stop_concurrent(ctx);
          if (!guards_false.empty()) {
            return fail(Failure(FailureCode::kNoTransition,
                                current_ + " " + to_string(m.type) + " and no guard holds (" +
                                    guards_false + ")" +
                                    (m.failure ? "; it said " + m.failure->reason() : ""),
                                where));
          }
          if (m.type == MessageType::kFailed && m.failure) {
            return fail(Failure(m.failure->code, m.failure->detail, where));
          }
          return fail(Failure(FailureCode::kNoTransition,
                              current_ + " " + to_string(m.type) + " and no transition", where));
        }
        continue;
      }
      if (source == current_ && terminal) current_child_ = -1;
      last_failure_ = m.failure;
      if (last_failure_) last_failure_->path = m.type == MessageType::kFailed ? where : "";
      for (const std::string& name : t->stop) {
        const auto it = concurrent_ids_.find(name);
        if (it != concurrent_ids_.end()) ctx.halt_child(it->second);
        concurrent_ids_.erase(name);
      }
      for (const std::string& name : t->start) start_concurrent(ctx, *find_concurrent(spec_, name));
      if (!t->to.empty()) enter(ctx, t->to);
    }
    if (!done_) return ProgramState::kRunning;
    stop_concurrent(ctx);
    if (success_) return ProgramState::kCompleted;
    if (!last_failure_) {
      return fail(FailureCode::kFailureState,
                  "final state " + current_ + ", which is not a success");
    }
    return fail(*last_failure_);
  }

 private:
  // A state's or concurrent program's step of a failure path: "program(state)".
  std::string step_label(const std::string& source) const {
    if (const MachineState* s = find_state(spec_, source)) return path_step(s->program, source);
    if (const ConcurrentProgram* c = find_concurrent(spec_, source))
      return path_step(c->program, source);
    return source;
  }

  void stop_concurrent(ProgramContext& ctx) {
    for (const auto& [name, id] : concurrent_ids_) ctx.halt_child(id);
    concurrent_ids_.clear();
  }

  void start_concurrent(ProgramContext& ctx, const ConcurrentProgram& c) {
    const auto running = concurrent_ids_.find(c.name);
    if (running != concurrent_ids_.end()) ctx.halt_child(running->second);
    concurrent_ids_[c.name] = ctx.start_child(c.program, substitute(c.params, params_));
  }

  void enter(ProgramContext& ctx, const std::string& state) {
    if (current_child_ >= 0) ctx.halt_child(current_child_);
    current_child_ = -1;
    current_ = state;
    const MachineState& s = *find_state(spec_, state);
    const auto invariant = invariants_.find(state);
    invariant_ = invariant == invariants_.end() ? nullptr : invariant->second;
    if (s.final) {
      done_ = true;
      success_ = s.success;
      return;
    }
    // A refused child has already sent its failure to the inbox; step() handles it.
    current_child_ = ctx.start_child(s.program, substitute(s.params, params_));
  }

  MachineSpec spec_;
  Params params_;
  std::string current_;
  int current_child_ = -1;
  std::map<std::string, int> concurrent_ids_;
  bool done_ = false, success_ = false;
  std::optional<Failure> last_failure_;             // of the last message that took a transition
  std::vector<ConditionPtr> guards_;                // per transition; null: none
  std::map<std::string, ConditionPtr> invariants_;  // by state
  ConditionPtr invariant_;                          // of the current state
  static constexpr int kInvariantSender = -2;
};

}  // namespace

void check_machine(const MachineSpec& spec, const ProgramRegistry& registry) {
  const std::string m = "machine '" + spec.name + "'";
  if (spec.name.empty()) throw std::invalid_argument("a machine needs a name");
  if (spec.states.empty()) throw std::invalid_argument(m + ": has no states");
  std::set<std::string> names;
  bool any_final = false;
  for (const MachineState& s : spec.states) {
    if (!names.insert(s.name).second)
      throw std::invalid_argument(m + ": state '" + s.name + "' is declared twice");
    if (s.final) {
      any_final = true;
      continue;
    }
    if (s.program == spec.name) {
      throw std::invalid_argument(m + ": state '" + s.name + "' runs the machine itself");
    }
    check_program_params(spec, registry, s.program, s.params, m + ", state '" + s.name + "'");
    if (!s.invariant.empty())
      check_condition(spec, s.invariant, m + ", state '" + s.name + "' invariant");
  }
  for (const ConcurrentProgram& c : spec.concurrent) {
    if (names.count(c.name))
      throw std::invalid_argument(m + ": concurrent program '" + c.name + "' has a state's name");
    check_program_params(spec, registry, c.program, c.params,
                         m + ", concurrent program '" + c.name + "'");
  }
  if (!any_final) throw std::invalid_argument(m + ": has no final state");
  if (!find_state(spec, spec.initial))
    throw std::invalid_argument(m + ": initial state '" + spec.initial + "' is not a state");
  for (size_t k = 0; k < spec.transitions.size(); ++k) {
    const MachineTransition& t = spec.transitions[k];
    const std::string where = m + ", transition " + std::to_string(k) + " (from " + t.from + ")";
    const MachineState* from = find_state(spec, t.from);
    if (!from && !find_concurrent(spec, t.from))
      throw std::invalid_argument(where + ": '" + t.from +
                                  "' is neither a state nor a concurrent program");
    if (from && from->final) throw std::invalid_argument(where + ": leaves a final state");
    if (!t.to.empty() && !find_state(spec, t.to))
      throw std::invalid_argument(where + ": target '" + t.to + "' is not a state");
    if (!t.when.empty()) check_condition(spec, t.when, where + " guard");
    for (const std::string& c : t.start)
      if (!find_concurrent(spec, c))
        throw std::invalid_argument(where + ": starts unknown concurrent program '" + c + "'");
    for (const std::string& c : t.stop)
      if (!find_concurrent(spec, c))
        throw std::invalid_argument(where + ": stops unknown concurrent program '" + c + "'");
  }
  for (const MachineState& s : spec.states) {
    if (s.final) continue;
    const bool handled = std::any_of(spec.transitions.begin(), spec.transitions.end(),
                                     [&](const MachineTransition& t) {
                                       return t.from == s.name && t.on == MessageType::kCompleted;
                                     });
    if (!handled)
      throw std::invalid_argument(m + ": state '" + s.name + "' has no transition on completed");
  }
}

void register_machine(const MachineSpec& spec, ProgramRegistry& registry) {
  check_machine(spec, registry);
  ProgramType type;
  type.name = spec.name;
  type.doc = spec.doc;
  type.params = spec.params;
  type.make = [spec](const Params& params) {
    return std::make_unique<StateMachineProgram>(spec, params);
  };
  type.machine = std::make_shared<const MachineSpec>(spec);
  registry.add(std::move(type));
}

std::vector<std::string> machine_warnings(const MachineSpec& spec) {
  std::vector<std::string> out;
  const std::string m = "machine '" + spec.name + "'";
  // States reached from the initial one by transitions, which fire from states reached and
  // from concurrent programs started (with the machine, or by a transition that fires).
  std::set<std::string> reached{spec.initial}, started;
  for (const ConcurrentProgram& c : spec.concurrent) {
    if (c.at_start) started.insert(c.name);
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (const MachineTransition& t : spec.transitions) {
      if (!reached.count(t.from) && !started.count(t.from)) continue;
      if (!t.to.empty() && reached.insert(t.to).second) grew = true;
      for (const std::string& c : t.start) grew = started.insert(c).second || grew;
    }
  }
  for (const MachineState& s : spec.states) {
    if (!reached.count(s.name)) {
      out.push_back(m + ": state '" + s.name +
                    "' is never reached: no transition leads to it from '" + spec.initial + "'");
    }
  }
  const bool succeeds = std::any_of(
      spec.states.begin(), spec.states.end(),
      [&](const MachineState& s) { return s.final && s.success && reached.count(s.name) > 0; });
  if (!succeeds) {
    out.push_back(m + ": no final state with success is reached, so the machine can only fail");
  }
  return out;
}

namespace {

// Where a call's parameter got its value: the outermost call's parameter ("" when a machine
// wrote it, or a program's own default), and where that machine wrote it.
struct Origin {
  std::string param = "";
  bool defaulted = false;
  std::string file = "";
  SourceSpot spot = {};
};

// Machines nest only through programs registered before them, so this bounds nothing real.
constexpr int kMaxNesting = 64;

// `origins`: of the parameters the call gives; the others are the program's defaults, written
// where `call` says.
void collect_names(const ProgramRegistry& registry, const std::string& program,
                   const RawParams& raw, const std::map<std::string, Origin>& origins,
                   const Origin& call, const std::string& path, int depth,
                   std::vector<NameUse>& out) {
  const ProgramType* type = registry.find(program);
  if (type == nullptr || depth > kMaxNesting) return;
  Params params;
  try {
    params = check_params(type->params, raw);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  auto origin_of = [&](const std::string& param) {
    const auto it = origins.find(param);
    return it != origins.end() ? it->second : Origin{"", true, call.file, call.spot};
  };
  const MachineSpec* machine = type->machine.get();
  for (const ParamSpec& p : type->params) {
    if (p.names == NameKind::kNone || p.type != ParamType::kString) continue;
    const std::string& value = params.text(p.name);
    if (value.empty()) continue;  // an optional parameter left out
    const Origin o = origin_of(p.name);
    out.push_back(
        {value, o.param, o.defaulted, path + ": parameter '" + p.name + "'", o.file, o.spot});
  }
  if (machine == nullptr) return;
  const MachineSpec& m = *machine;
  // Each parameter of a program the machine calls: "$x" takes x's origin, the rest are the
  // machine's own writing.
  auto call_origins = [&](const RawParams& given, const SourceSpot& spot) {
    std::map<std::string, Origin> o;
    for (const auto& [key, value] : given) {
      o[key] = !value.empty() && value.front() == '$' ? origin_of(value.substr(1))
                                                      : Origin{"", false, m.source, spot};
    }
    return o;
  };
  auto condition_names = [&](const std::string& text, const SourceSpot& spot,
                             const std::string& where) {
    for (const std::string& word : condition_object_names(text)) {
      // "$x" alone is the parameter x's value; a word with "$x" inside is the machine's own.
      const std::string name = substitute_condition(word, params);
      const std::string ref = word.size() > 1 && word.front() == '$' ? word.substr(1) : "";
      const bool whole = !ref.empty() && params.values().count(ref) > 0;
      const Origin o = whole ? origin_of(ref) : Origin{"", false, m.source, spot};
      out.push_back({name, o.param, o.defaulted, where, o.file, o.spot});
    }
  };
  for (const ConcurrentProgram& c : m.concurrent) {
    collect_names(registry, c.program, substitute(c.params, params), call_origins(c.params, c.spot),
                  Origin{"", true, m.source, c.spot}, path + " > " + c.program + "(" + c.name + ")",
                  depth + 1, out);
  }
  for (const MachineState& st : m.states) {
    if (st.final) continue;
    collect_names(registry, st.program, substitute(st.params, params),
                  call_origins(st.params, st.spot), Origin{"", true, m.source, st.spot},
                  path + " > " + st.program + "(" + st.name + ")", depth + 1, out);
    if (!st.invariant.empty()) {
      condition_names(st.invariant, st.spot, path + ", state '" + st.name + "' invariant");
    }
  }
  for (size_t k = 0; k < m.transitions.size(); ++k) {
    const MachineTransition& t = m.transitions[k];
    if (t.when.empty()) continue;
    condition_names(t.when, t.spot,
                    path + ", transition " + std::to_string(k) + " (from " + t.from + ") guard");
  }
}

}  // namespace

std::vector<NameUse> names_used(const ProgramRegistry& registry, const std::string& program,
                                const RawParams& params) {
  std::vector<NameUse> out;
  const ProgramType* type = registry.find(program);
  if (type == nullptr) return out;
  std::map<std::string, Origin> origins;
  for (const ParamSpec& p : type->params) origins[p.name] = {p.name, params.count(p.name) == 0};
  collect_names(registry, program, params, origins, Origin{}, program, 0, out);
  return out;
}

}  // namespace taskmatrix::core
