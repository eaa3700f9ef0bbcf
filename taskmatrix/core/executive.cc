#include "taskmatrix/core/executive.h"

#include <stdexcept>

namespace taskmatrix::core {

struct Executive::Instance {
  int id = -1;
  int parent = -1;
  std::string name;
  std::unique_ptr<TaskProgram> program;
  std::unique_ptr<Context> context;
  std::vector<std::string> chains;
  std::vector<int> children;
  std::vector<Message> inbox;
  bool running = false;
  bool started = false;
  std::optional<Message> outcome;
  std::map<std::string, size_t> series;  // name -> index into Executive::series_
};

class Executive::Context final : public ProgramContext {
 public:
  Context(Executive& e, int id) : e_(e), id_(id) {}
  Skillset& skills() override { return e_.skills_; }
  const PerceptualModel& percepts() const override { return e_.percepts_; }
  double time() const override { return e_.skills_.time(); }
  int self() const override { return id_; }
  void emit(MessageType type, std::optional<Failure> failure,
            std::shared_ptr<const PlanResult> plan) override {
    e_.emit(id_, type, std::move(failure), std::move(plan));
  }
  const PlanOptions& plan_options() const override { return e_.options_.plan; }
  std::uint32_t next_seed() override { return e_.next_seed(); }
  int start_child(const std::string& program, const RawParams& params) override {
    std::unique_ptr<TaskProgram> p = e_.registry_.instantiate(program, params);
    return e_.launch(std::move(p), program, id_);
  }
  void halt_child(int id) override { e_.halt(id); }
  std::vector<Message> take_inbox() override {
    std::vector<Message> out;
    out.swap(e_.instances_.at(id_)->inbox);
    return out;
  }
  void record(const std::string& series, double value) override {
    Instance& inst = *e_.instances_.at(id_);
    auto it = inst.series.find(series);
    if (it == inst.series.end()) {
      e_.series_.push_back(RecordedSeries{id_, inst.name, series, {}});
      it = inst.series.emplace(series, e_.series_.size() - 1).first;
    }
    e_.series_[it->second].samples.emplace_back(e_.skills_.time(), value);
  }
  std::vector<std::string>& notes(const std::string& key) override { return e_.notes_[key]; }

 private:
  Executive& e_;
  int id_;
};

Executive::Executive(Skillset& skills, const ProgramRegistry& registry, Perception* perception,
                     ExecutiveOptions options)
    : skills_(skills), registry_(registry), perception_(perception), options_(std::move(options)) {
  if (options_.seed == 0) throw std::invalid_argument("executive seed must be positive");
  if (!(options_.perception_rate_hz > 0)) {
    throw std::invalid_argument("perception rate must be positive");
  }
  perceive();
}

Executive::~Executive() = default;

void Executive::perceive() {
  if (perception_) perception_->update(skills_.time(), percepts_);
  next_perception_ = skills_.time() + 1.0 / options_.perception_rate_hz;
}

int Executive::start(const std::string& program, const RawParams& params) {
  return launch(registry_.instantiate(program, params), program, -1);
}

int Executive::start(std::unique_ptr<TaskProgram> program, const std::string& name) {
  return launch(std::move(program), name, -1);
}

std::uint32_t Executive::next_seed() {
  // splitmix64 of the run seed and a counter: distinct, reproducible, never 0.
  std::uint64_t z = (static_cast<std::uint64_t>(options_.seed) << 32) + ++seed_counter_;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return static_cast<std::uint32_t>(z % 0xfffffffeULL) + 1;
}

template <typename F>
bool Executive::contained(int id, F&& what) {
  try {
    what();
    return true;
  } catch (const std::invalid_argument& e) {
    finish(id, MessageType::kFailed, Failure{FailureCode::kInvalidInput, e.what()});
  } catch (const std::exception& e) {
    finish(id, MessageType::kFailed,
           Failure{FailureCode::kProgramError, instances_.at(id)->name + ": " + e.what()});
  } catch (...) {
    finish(id, MessageType::kFailed,
           Failure{FailureCode::kProgramError,
                   instances_.at(id)->name + ": an exception of unknown type"});
  }
  return false;
}

void Executive::emit(int id, MessageType type, std::optional<Failure> failure,
                     std::shared_ptr<const PlanResult> plan) {
  Instance& inst = *instances_.at(id);
  Message m{skills_.time(), id, inst.name, type, std::move(failure), std::move(plan)};
  log_.push_back(m);
  if (inst.parent >= 0) {
    const auto parent = instances_.find(inst.parent);
    if (parent != instances_.end() && parent->second->running) parent->second->inbox.push_back(m);
  }
}

int Executive::launch(std::unique_ptr<TaskProgram> program, const std::string& name, int parent) {
  const int id = next_id_++;
  auto inst = std::make_unique<Instance>();
  inst->id = id;
  inst->parent = parent;
  inst->name = name;
  inst->program = std::move(program);
  inst->context = std::make_unique<Context>(*this, id);
  Instance& self = *inst;
  instances_.emplace(id, std::move(inst));
  if (parent >= 0) instances_.at(parent)->children.push_back(id);
  self.running = true;

  std::vector<std::string> chains;
  const bool claimed = contained(id, [&] {
    const ClaimContext claim{
        skills_, percepts_, [this](const std::string& c) { return chain_holder_.count(c) > 0; },
        next_seed(),
        [this](const std::vector<std::string>& names, const std::vector<double>& values) {
          return skills_.is_valid(names, values);
        }};
    chains = self.program->claim(claim);
  });
  if (!claimed) return id;
  for (const std::string& c : chains) {
    const auto held = chain_holder_.find(c);
    if (held != chain_holder_.end()) {
      const Instance& other = *instances_.at(held->second);
      finish(id, MessageType::kFailed,
             Failure{FailureCode::kChainsBusy,
                     c + " held by " + other.name + "#" + std::to_string(other.id)});
      return id;
    }
  }
  for (const std::string& c : chains) chain_holder_[c] = id;
  self.chains = chains;
  emit(id, MessageType::kStarted);
  ConditionPtr pre;
  bool holds = true;
  if (!contained(id, [&] {
        pre = self.program->precondition();
        holds = !pre || pre->holds(World{skills_, percepts_});
      })) {
    return id;
  }
  if (!holds) {
    finish(id, MessageType::kFailed,
           Failure{FailureCode::kPreconditionFalse, pre->explain(World{skills_, percepts_})});
    return id;
  }
  if (contained(id, [&] { self.program->start(*self.context); })) self.started = true;
  return id;
}

void Executive::finish(int id, MessageType type, std::optional<Failure> failure) {
  Instance& inst = *instances_.at(id);
  if (!inst.running) return;
  for (int child : inst.children) halt(child);
  for (const std::string& c : inst.chains) {
    const auto it = chain_holder_.find(c);
    if (it != chain_holder_.end() && it->second == id) chain_holder_.erase(it);
  }
  emit(id, type, std::move(failure));
  refresh_percepts_ = true;
  inst.running = false;
  inst.outcome = log_.back();
}

void Executive::halt(int id) {
  const auto it = instances_.find(id);
  if (it == instances_.end() || !it->second->running) return;
  Instance& inst = *it->second;
  for (int child : inst.children) halt(child);
  if (inst.started && !contained(id, [&] { inst.program->halt(*inst.context); })) return;
  finish(id, MessageType::kHalted);
}

void Executive::tick() {
  if (refresh_percepts_ || skills_.time() >= next_perception_ - 1e-12) perceive();
  refresh_percepts_ = false;
  std::vector<int> ids;
  for (const auto& [id, inst] : instances_) {
    if (inst->running) ids.push_back(id);
  }
  for (int id : ids) {
    Instance& inst = *instances_.at(id);
    if (!inst.running) continue;  // ended by an earlier program's step this tick
    ProgramState state = ProgramState::kRunning;
    if (!contained(id, [&] { state = inst.program->step(*inst.context); })) continue;
    if (state == ProgramState::kCompleted) finish(id, MessageType::kCompleted);
    if (state == ProgramState::kFailed) finish(id, MessageType::kFailed, inst.program->failure());
  }
  const StepReport step = skills_.advance();
  if (step.unstable) {
    for (int id : ids) {
      if (instances_.at(id)->running && instances_.at(id)->parent < 0)
        finish(id, MessageType::kFailed, Failure{FailureCode::kSimUnstable, step.message});
    }
  }
}

bool Executive::run(double max_time_s) {
  const double until = skills_.time() + max_time_s;
  while (any_running() && skills_.time() < until - 1e-12) tick();
  return !any_running();
}

bool Executive::running(int id) const {
  const auto it = instances_.find(id);
  return it != instances_.end() && it->second->running;
}

bool Executive::any_running() const {
  for (const auto& [id, inst] : instances_) {
    if (inst->running) return true;
  }
  return false;
}

const Message* Executive::outcome(int id) const {
  const auto it = instances_.find(id);
  if (it == instances_.end() || !it->second->outcome) return nullptr;
  return &*it->second->outcome;
}

const RecordedSeries* Executive::find_series(const std::string& program,
                                             const std::string& name) const {
  for (const RecordedSeries& s : series_) {
    if (s.program == program && s.name == name) return &s;
  }
  return nullptr;
}

int Executive::holder_of_chain(const std::string& chain) const {
  const auto it = chain_holder_.find(chain);
  return it == chain_holder_.end() ? -1 : it->second;
}

}  // namespace taskmatrix::core
