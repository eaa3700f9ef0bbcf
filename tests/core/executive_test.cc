// The executive and state machines, with small test programs on the fake skillset (no
// simulator: core logic alone).
#include "taskmatrix/core/executive.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/io/machine_file.h"
#include "tests/support/fake_skillset.h"

namespace taskmatrix::core {
namespace {

// Moves the first joint of each chain by `delta` over `duration` s, then ends with `outcome`.
class Sweep final : public TaskProgram {
 public:
  explicit Sweep(const Params& p)
      : chains_(p.list("chains")),
        duration_(p.number("duration")),
        delta_(p.number("delta")),
        outcome_(p.text("outcome")) {}
  std::vector<std::string> chains(const Skillset& skills) const override {
    for (const std::string& c : chains_) skills.chain(c);  // throws for unknown chains
    return chains_;
  }
  ConditionPtr precondition() const override { return precondition_; }
  void start(ProgramContext& ctx) override {
    t0_ = ctx.time();
    q0_ = ctx.skills().configuration(chains_);
  }
  ProgramState step(ProgramContext& ctx) override {
    const double s = std::min(1.0, (ctx.time() - t0_) / duration_);
    std::vector<double> q = q0_;
    size_t i = 0;
    for (const std::string& c : chains_) {
      q[i] += s * delta_;
      i += ctx.skills().chain(c).joints.size();
    }
    ctx.skills().command(chains_, q);
    if (s < 1.0) return ProgramState::kRunning;
    if (outcome_ == "failed") return fail("test_failure: asked to fail");
    return ProgramState::kCompleted;
  }
  ConditionPtr precondition_;

 private:
  std::vector<std::string> chains_;
  double duration_, delta_;
  std::string outcome_;
  double t0_ = 0;
  std::vector<double> q0_;
};

// Holds its chains; throws `what` from step() after `after` ticks.
class Thrower final : public TaskProgram {
 public:
  explicit Thrower(const Params& p) : chains_(p.list("chains")), after_(p.number("after")) {}
  std::vector<std::string> chains(const Skillset&) const override { return chains_; }
  void start(ProgramContext&) override {}
  ProgramState step(ProgramContext&) override {
    if (ticks_++ >= after_) throw std::runtime_error("the test program threw");
    return ProgramState::kRunning;
  }

 private:
  std::vector<std::string> chains_;
  double after_;
  int ticks_ = 0;
};

ProgramRegistry test_registry() {
  ProgramRegistry r;
  r.add({"thrower",
         "test program that throws",
         {{"chains", ParamType::kStringList, true, {}, {}, ""},
          {"after", ParamType::kNumber, false, 5.0, {}, ""}},
         [](const Params& p) { return std::make_unique<Thrower>(p); }});
  r.add({"sweep",
         "test program",
         {{"chains", ParamType::kStringList, true, {}, {}, ""},
          {"duration", ParamType::kNumber, false, 0.2, {}, ""},
          {"delta", ParamType::kNumber, false, 0.0, {}, ""},
          {"outcome",
           ParamType::kString,
           false,
           std::string("completed"),
           {"completed", "failed"},
           ""}},
         [](const Params& p) { return std::make_unique<Sweep>(p); }});
  r.add({"wait_for_wave", "test program with a precondition", {}, [](const Params&) {
           Params p({{"chains", std::vector<std::string>{"head"}},
                     {"duration", 0.1},
                     {"delta", 0.0},
                     {"outcome", std::string("completed")}});
           auto s = std::make_unique<Sweep>(p);
           s->precondition_ = postural("wave_start");
           return s;
         }});
  return r;
}

class ExecutiveTest : public ::testing::Test {
 protected:
  void SetUp() override {
    skills_ = std::make_unique<test::FakeSkillset>(test::fake_kitchen());
    perception_ = std::make_unique<test::FakePerception>(*skills_);
    registry_ = test_registry();
    exec_ = std::make_unique<Executive>(*skills_, registry_, perception_.get());
  }
  std::vector<std::string> log_of(int id) const {
    std::vector<std::string> out;
    for (const Message& m : exec_->log()) {
      if (m.sender == id) out.push_back(to_string(m.type));
    }
    return out;
  }
  std::unique_ptr<test::FakeSkillset> skills_;
  std::unique_ptr<test::FakePerception> perception_;
  ProgramRegistry registry_;
  std::unique_ptr<Executive> exec_;
};

TEST_F(ExecutiveTest, ProgramsOnDisjointChainsProgressTogether) {
  const double l0 = skills_->configuration({"left_arm"})[0];
  const double r0 = skills_->configuration({"right_arm"})[0];
  const int a =
      exec_->start("sweep", {{"chains", "[left_arm]"}, {"duration", "1"}, {"delta", "0.3"}});
  const int b =
      exec_->start("sweep", {{"chains", "[right_arm]"}, {"duration", "1"}, {"delta", "0.3"}});
  EXPECT_TRUE(exec_->running(a));
  EXPECT_TRUE(exec_->running(b));
  exec_->run(0.5);
  // Half way: both arms have moved.
  EXPECT_GT(std::abs(skills_->configuration({"left_arm"})[0] - l0), 0.08);
  EXPECT_GT(std::abs(skills_->configuration({"right_arm"})[0] - r0), 0.08);
  EXPECT_TRUE(exec_->running(a) && exec_->running(b));
  EXPECT_TRUE(exec_->run(5.0));
  EXPECT_EQ(exec_->outcome(a)->type, MessageType::kCompleted);
  EXPECT_EQ(exec_->outcome(b)->type, MessageType::kCompleted);
  EXPECT_EQ(log_of(a), (std::vector<std::string>{"started", "completed"}));
  EXPECT_EQ(exec_->holder_of_chain("left_arm"), -1);
}

TEST_F(ExecutiveTest, AProgramAskingForAHeldChainIsRefusedAndTheHolderContinues) {
  const int a = exec_->start("sweep", {{"chains", "[left_arm]"}, {"duration", "1"}});
  const int b = exec_->start("sweep", {{"chains", "[head, left_arm]"}});
  EXPECT_FALSE(exec_->running(b));
  ASSERT_NE(exec_->outcome(b), nullptr);
  EXPECT_EQ(exec_->outcome(b)->type, MessageType::kFailed);
  EXPECT_EQ(exec_->outcome(b)->reason, "chains_busy: left_arm held by sweep#" + std::to_string(a));
  EXPECT_EQ(exec_->holder_of_chain("head"), -1);  // nothing of the refused program is held
  EXPECT_TRUE(exec_->running(a));
  EXPECT_EQ(exec_->holder_of_chain("left_arm"), a);
  EXPECT_TRUE(exec_->run(5.0));
  EXPECT_EQ(exec_->outcome(a)->type, MessageType::kCompleted);
}

TEST_F(ExecutiveTest, ForcedTerminationFreesTheChainsAtOnce) {
  const int a =
      exec_->start("sweep", {{"chains", "[torso, head]"}, {"duration", "30"}, {"delta", "0.2"}});
  for (int k = 0; k < 20; ++k) exec_->tick();
  exec_->halt(a);
  EXPECT_FALSE(exec_->running(a));
  EXPECT_EQ(exec_->outcome(a)->type, MessageType::kHalted);
  EXPECT_EQ(exec_->holder_of_chain("torso"), -1);
  // Halted where it was: the torso holds its position.
  const std::vector<double> q = skills_->configuration({"torso"});
  for (int k = 0; k < 50; ++k) exec_->tick();
  const std::vector<double> later = skills_->configuration({"torso"});
  for (size_t i = 0; i < q.size(); ++i) EXPECT_NEAR(later[i], q[i], 0.01);
  const int b = exec_->start("sweep", {{"chains", "[torso]"}});
  EXPECT_TRUE(exec_->running(b));
}

TEST_F(ExecutiveTest, APreconditionThatIsFalseFailsTheProgramBeforeItRuns) {
  const int a = exec_->start("wait_for_wave", {});
  ASSERT_NE(exec_->outcome(a), nullptr);
  // The reason says which joint is how far from the posture.
  const std::string reason = exec_->outcome(a)->reason;
  EXPECT_EQ(reason.rfind("precondition_false: postural(wave_start): joint ", 0), 0u) << reason;
  EXPECT_NE(reason.find(" from the posture (tolerance "), std::string::npos) << reason;
  EXPECT_EQ(exec_->holder_of_chain("head"), -1);
}

TEST_F(ExecutiveTest, BadParametersAreRejectedBeforeAnythingRuns) {
  auto error = [&](const RawParams& p) {
    try {
      exec_->start("sweep", p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error({}), "program 'sweep': parameter 'chains' (list of strings) is required");
  EXPECT_EQ(error({{"chains", "[head]"}, {"duration", "soon"}}),
            "program 'sweep': parameter 'duration': 'soon' is not a finite number");
  EXPECT_EQ(error({{"chains", "[head]"}, {"outcome", "maybe"}}),
            "program 'sweep': parameter 'outcome': 'maybe' is not one of: completed, failed");
  EXPECT_NE(error({{"chains", "[head]"}, {"speed", "1"}}).find("parameter 'speed' is unknown"),
            std::string::npos);
  EXPECT_EQ(error({{"chains", "[head]"}, {"duration", "nan"}}),
            "program 'sweep': parameter 'duration': 'nan' is not a finite number");
  EXPECT_THROW(exec_->start("moonwalk", {}), std::invalid_argument);
  EXPECT_FALSE(exec_->any_running());
  // An unknown chain is found when the program asks for it: it fails, nothing is held.
  const int a = exec_->start("sweep", {{"chains", "[tail]"}});
  EXPECT_EQ(exec_->outcome(a)->type, MessageType::kFailed);
  EXPECT_NE(exec_->outcome(a)->reason.find("invalid_input: "), std::string::npos);
}

TEST_F(ExecutiveTest, AProgramThatThrowsFailsWithProgramErrorAndTheOthersRunOn) {
  const int bad = exec_->start("thrower", {{"chains", "[head]"}});
  const int good =
      exec_->start("sweep", {{"chains", "[left_arm]"}, {"duration", "0.5"}, {"delta", "0.1"}});
  EXPECT_TRUE(exec_->run(5.0));
  ASSERT_NE(exec_->outcome(bad), nullptr);
  EXPECT_EQ(exec_->outcome(bad)->type, MessageType::kFailed);
  EXPECT_EQ(exec_->outcome(bad)->reason, "program_error: thrower: the test program threw");
  EXPECT_EQ(exec_->holder_of_chain("head"), -1);
  EXPECT_EQ(exec_->outcome(good)->type, MessageType::kCompleted);
}

TEST_F(ExecutiveTest, HaltingAChainAHairPastItsLimitHoldsItAtTheLimit) {
  const int a = exec_->start("sweep", {{"chains", "[head]"}, {"duration", "30"}});
  for (int k = 0; k < 5; ++k) exec_->tick();
  // Every joint of the head a hair past its upper limit, as a joint settled on a soft limit
  // is measured.
  std::vector<double> past = skills_->chain("head").upper;
  for (double& v : past) v += 1e-4;
  skills_->place({"head"}, past);
  exec_->halt(a);
  EXPECT_EQ(exec_->outcome(a)->type, MessageType::kHalted) << exec_->outcome(a)->reason;
  EXPECT_EQ(skills_->clamped_configuration({"head"}), skills_->chain("head").upper);
}

MachineSpec two_step_machine(const std::string& second_outcome) {
  MachineSpec m;
  m.name = "two_step";
  m.params = {{"arm", ParamType::kStringList, true, {}, {}, ""}};
  m.states = {
      {"first", "sweep", {{"chains", "$arm"}, {"delta", "0.1"}}, false, true, ""},
      {"second", "sweep", {{"chains", "[head]"}, {"outcome", second_outcome}}, false, true, ""},
      {"recover", "sweep", {{"chains", "[torso]"}}, false, true, ""},
      {"done", "", {}, true, true, ""},
      {"gave_up", "", {}, true, false, ""}};
  m.initial = "first";
  m.transitions = {{"first", MessageType::kCompleted, "second", {}, {}, ""},
                   {"second", MessageType::kCompleted, "done", {}, {}, ""},
                   {"second", MessageType::kFailed, "recover", {}, {}, ""},
                   {"recover", MessageType::kCompleted, "gave_up", {}, {}, ""}};
  return m;
}

TEST_F(ExecutiveTest, StateMachineTransitionsOnMessagesToAFinalState) {
  register_machine(two_step_machine("completed"), registry_);
  const int m = exec_->start("two_step", {{"arm", "[left_arm]"}});
  EXPECT_TRUE(exec_->run(10.0));
  EXPECT_EQ(exec_->outcome(m)->type, MessageType::kCompleted);
  std::vector<std::string> sequence;
  for (const Message& msg : exec_->log()) {
    if (msg.program == "sweep") sequence.push_back(std::string(to_string(msg.type)));
  }
  EXPECT_EQ(sequence, (std::vector<std::string>{"started", "completed", "started", "completed"}));
}

TEST_F(ExecutiveTest, AFailureTakesTheFailureTransitionAndEndsInAFailureState) {
  register_machine(two_step_machine("failed"), registry_);
  const int m = exec_->start("two_step", {{"arm", "[right_arm]"}});
  EXPECT_TRUE(exec_->run(10.0));
  EXPECT_EQ(exec_->outcome(m)->type, MessageType::kFailed);
  // The failure went through `recover` (a third sweep, on the torso) to `gave_up`.
  std::vector<int> sweeps;
  for (const Message& msg : exec_->log()) {
    if (msg.program == "sweep" && msg.type == MessageType::kStarted) sweeps.push_back(msg.sender);
  }
  ASSERT_EQ(sweeps.size(), 3u);
  EXPECT_EQ(exec_->outcome(sweeps[1])->reason, "test_failure: asked to fail");
  EXPECT_EQ(exec_->outcome(sweeps[2])->type, MessageType::kCompleted);
  EXPECT_EQ(exec_->outcome(m)->reason, "final state gave_up");
}

TEST_F(ExecutiveTest, AFailureWithNoTransitionFailsTheMachineWithTheSameReason) {
  MachineSpec m = two_step_machine("failed");
  m.transitions.erase(m.transitions.begin() + 2);  // no "second failed" transition
  register_machine(m, registry_);
  const int id = exec_->start("two_step", {{"arm", "[left_arm]"}});
  EXPECT_TRUE(exec_->run(10.0));
  EXPECT_EQ(exec_->outcome(id)->reason, "test_failure: asked to fail");
  EXPECT_EQ(exec_->outcome(id)->path, "sweep(second)");
}

TEST_F(ExecutiveTest, AnInvariantThatStopsHoldingSaysWhatWasMeasured) {
  MachineSpec m = two_step_machine("completed");
  m.states[0].params["delta"] = "0.5";
  m.states[0].invariant = "postural(rest)";
  register_machine(m, registry_);
  const int id = exec_->start("two_step", {{"arm", "[left_arm]"}});
  EXPECT_TRUE(exec_->run(10.0));
  const Message& failed = *exec_->outcome(id);
  EXPECT_EQ(failed.type, MessageType::kFailed);
  EXPECT_EQ(failed.reason.rfind("invariant_false: postural(rest): joint ", 0), 0u) << failed.reason;
  EXPECT_NE(failed.reason.find(" from the posture (tolerance "), std::string::npos)
      << failed.reason;
  EXPECT_EQ(failed.path, "sweep(first)");
}

TEST_F(ExecutiveTest, AFailureInANestedMachineNamesThePathToTheStateThatFailed) {
  MachineSpec inner = two_step_machine("failed");
  inner.transitions.erase(inner.transitions.begin() + 2);  // no "second failed" transition
  register_machine(inner, registry_);
  MachineSpec outer;
  outer.name = "outer";
  outer.states = {{"inner", "two_step", {{"arm", "[right_arm]"}}, false, true, ""},
                  {"end", "", {}, true, true, ""}};
  outer.initial = "inner";
  outer.transitions = {{"inner", MessageType::kCompleted, "end", {}, {}, ""}};
  register_machine(outer, registry_);
  const int id = exec_->start("outer", {});
  EXPECT_TRUE(exec_->run(10.0));
  const Message& failed = *exec_->outcome(id);
  EXPECT_EQ(failed.type, MessageType::kFailed);
  EXPECT_EQ(failed.reason, "test_failure: asked to fail");
  EXPECT_EQ(failed.path, "two_step(inner) > sweep(second)");
  const std::string text = failure_text("outer", failed);
  EXPECT_EQ(text, "outer > two_step(inner) > sweep(second): test_failure: asked to fail");
  EXPECT_EQ(failure_status(text), "test_failure");
  EXPECT_EQ(failure_status("ik_failure: no pose: 3 tried"), "ik_failure");
}

TEST_F(ExecutiveTest, MachinesNestAndHaltingOneHaltsItsChildren) {
  register_machine(two_step_machine("completed"), registry_);
  MachineSpec outer;
  outer.name = "outer";
  outer.states = {{"inner", "two_step", {{"arm", "[right_arm]"}}, false, true, ""},
                  {"end", "", {}, true, true, ""}};
  outer.initial = "inner";
  outer.transitions = {{"inner", MessageType::kCompleted, "end", {}, {}, ""}};
  outer.concurrent = {{"lean", "sweep", {{"chains", "[torso]"}, {"duration", "100"}}, true}};
  register_machine(outer, registry_);

  const int id = exec_->start("outer", {});
  EXPECT_TRUE(exec_->run(10.0));
  EXPECT_EQ(exec_->outcome(id)->type, MessageType::kCompleted) << exec_->outcome(id)->reason;
  // The concurrent torso program ran alongside and was stopped when the machine ended.
  EXPECT_EQ(exec_->holder_of_chain("torso"), -1);
  bool look_halted = false;
  for (const Message& msg : exec_->log()) look_halted |= msg.type == MessageType::kHalted;
  EXPECT_TRUE(look_halted);

  // Forced termination of the outer machine mid-way halts everything below it.
  const int again = exec_->start("outer", {});
  for (int k = 0; k < 10; ++k) exec_->tick();
  EXPECT_NE(exec_->holder_of_chain("right_arm"), -1);
  exec_->halt(again);
  EXPECT_FALSE(exec_->any_running());
  EXPECT_EQ(exec_->holder_of_chain("right_arm"), -1);
  EXPECT_EQ(exec_->holder_of_chain("torso"), -1);
}

TEST_F(ExecutiveTest, MachinesAreCheckedWhenRegistered) {
  auto error = [&](MachineSpec m) {
    try {
      register_machine(m, registry_);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  MachineSpec m = two_step_machine("completed");
  m.states[0].program = "moonwalk";
  EXPECT_EQ(error(m), "machine 'two_step', state 'first': unknown program 'moonwalk'");
  m = two_step_machine("completed");
  m.states[0].params["speed"] = "1";
  EXPECT_EQ(error(m),
            "machine 'two_step', state 'first': program 'sweep' has no parameter 'speed'");
  m = two_step_machine("completed");
  m.states[0].params["chains"] = "$legs";
  EXPECT_EQ(error(m),
            "machine 'two_step', state 'first': parameter 'chains' refers to $legs, which machine "
            "'two_step' does not declare");
  m = two_step_machine("completed");
  m.states[0].params["duration"] = "$arm";
  EXPECT_EQ(error(m),
            "machine 'two_step', state 'first': parameter 'duration' is a number but $arm is a "
            "list of strings");
  m = two_step_machine("completed");
  m.states[1].params["duration"] = "long";
  EXPECT_EQ(error(m),
            "machine 'two_step', state 'second': parameter 'duration': 'long' is not a finite "
            "number");
  m = two_step_machine("completed");
  m.transitions.erase(m.transitions.begin());
  EXPECT_EQ(error(m), "machine 'two_step': state 'first' has no transition on completed");
  m = two_step_machine("completed");
  m.transitions[0].to = "nowhere";
  EXPECT_EQ(error(m),
            "machine 'two_step', transition 0 (from first): target 'nowhere' is not a state");
  m = two_step_machine("completed");
  m.states.erase(m.states.begin() + 3, m.states.end());
  m.transitions.resize(1);
  EXPECT_EQ(error(m), "machine 'two_step': has no final state");
}

TEST_F(ExecutiveTest, MachinesFromYamlRunAndBadFilesNameFileLineAndKey) {
  // A fresh folder for the machine files.
  static std::atomic<int> serial{0};
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("taskmatrix-machines-" + std::to_string(getpid()) + "-" + std::to_string(serial++));
  std::filesystem::create_directories(dir);
  struct Remove {
    std::filesystem::path path;
    ~Remove() { std::filesystem::remove_all(path); }
  } remove{dir};
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
  };
  const std::string good = R"(name: wave_then_nod
doc: two sweeps in sequence
parameters:
  arm: {type: strings}
  amount: {type: number, default: 0.1}
concurrent:
  lean: {program: sweep, params: {chains: [torso], duration: 100}}
initial: swing
states:
  swing: {program: sweep, params: {chains: $arm, delta: $amount}}
  nod: {program: sweep, params: {chains: [head]}}
  done: {final: success}
transitions:
  - {from: swing, on: completed, to: nod}
  - {from: nod, on: completed, to: done, stop: [lean]}
)";
  write("good.yaml", good);
  io::load_and_register_machine(dir / "good.yaml", registry_);
  const int id = exec_->start("wave_then_nod", {{"arm", "[left_arm]"}});
  EXPECT_TRUE(exec_->run(10.0));
  EXPECT_EQ(exec_->outcome(id)->type, MessageType::kCompleted);

  auto error = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    write("bad.yaml", text);
    ProgramRegistry fresh = test_registry();
    try {
      io::load_and_register_machine(dir / "bad.yaml", fresh);
    } catch (const InputError& e) {
      return std::string(e.what()).substr(dir.string().size() + 1);
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("on: completed, to: nod", "on: finished, to: nod"),
            "bad.yaml:14: transitions[0].on: 'finished' is not a message (started, "
            "planning_started, planning_ended, completed, failed, halted)");
  EXPECT_EQ(error("nod: {program: sweep", "nod: {program: swep"),
            "bad.yaml:11: states.nod: machine 'wave_then_nod', state 'nod': unknown "
            "program 'swep'");
  EXPECT_EQ(error("delta: $amount", "delta: $arm"),
            "bad.yaml:10: states.swing: machine 'wave_then_nod', state 'swing': "
            "parameter 'delta' is a number but $arm is a list of strings");
  EXPECT_EQ(error("amount: {type: number, default: 0.1}", "amount: {type: number, default: lots}"),
            "bad.yaml:5: parameters.amount.default: 'lots' is not a finite number");
  EXPECT_EQ(error("initial: swing", "initial: swing\nrepeat: 2"),
            "bad.yaml:9: repeat: unknown key (expected one of: name, doc, parameters, "
            "concurrent, initial, states, transitions)");
}

}  // namespace
}  // namespace taskmatrix::core
