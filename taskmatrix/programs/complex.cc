// The complex task programs (paper section IV): state machines over the primitives, built
// through the same state-machine API a YAML machine file goes through (core/state_machine.h),
// so every program, parameter, guard and invariant is checked when they are registered.
//
//   pickup   object, side, step reach, then grasp, with fixate on the object running on the
//                               head (not the base) throughout
//   putdown  object, surface    position the held object onto a placement drawn from
//                               above(object, surface) and near(object, surface), release,
//                               lift the hand straight off it (retreat hand, up), then the
//                               torso and the free arms to rest; where that rest
//                               fails, a step back from the furniture and once more
//   greet    target, side       fixate on the target until it is centred (head and base);
//                               then, tracking it with the head alone, raise a free arm
//                               (postural wave_start) and wave (canned wave, while
//                               in_view(target) holds); tracking stops, the arm is lowered
//                               and it finds the target once more.
//                               Where the base cannot turn to the target or the arms cannot
//                               come down to rest, it steps back from the furniture
//                               (retreat), lowers the arms, and tries once more (lowering the
//                               torso's bend too; finding: twice, a second step back first); a
//                               target that leaves the view while the arm rises or waves is found
//                               again and waved at once more
//   vacuum   tool, surface      Fig. 4: pickup the tool; position its tip over the nearest
//                               debris while any is known; putdown the tool on the surface
#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

using core::MachineSpec;
using core::MachineState;
using core::MachineTransition;
using core::MessageType;
using core::ParamSpec;
using core::ParamType;

MachineState state(std::string name, std::string program, core::RawParams params,
                   std::string invariant = "") {
  MachineState s;
  s.name = std::move(name);
  s.program = std::move(program);
  s.params = std::move(params);
  s.invariant = std::move(invariant);
  return s;
}

MachineState final_state(std::string name, bool success) {
  MachineState s;
  s.name = std::move(name);
  s.final = true;
  s.success = success;
  return s;
}

MachineTransition on_completed(std::string from, std::string to, std::string when = "") {
  MachineTransition t;
  t.from = std::move(from);
  t.on = MessageType::kCompleted;
  t.to = std::move(to);
  t.when = std::move(when);
  return t;
}

ParamSpec text_param(std::string name, std::string doc, std::string default_value = "",
                     std::vector<std::string> choices = {}) {
  ParamSpec p;
  p.name = std::move(name);
  p.type = ParamType::kString;
  p.doc = std::move(doc);
  if (!default_value.empty()) {
    p.required = false;
    p.default_value = std::move(default_value);
  }
  p.choices = std::move(choices);
  return p;
}

ParamSpec integer_param(std::string name, std::string doc, std::int64_t default_value) {
  ParamSpec p;
  p.name = std::move(name);
  p.type = ParamType::kInteger;
  p.doc = std::move(doc);
  p.required = false;
  p.default_value = default_value;
  return p;
}

ParamSpec flag_param(std::string name, std::string doc, bool default_value) {
  ParamSpec p;
  p.name = std::move(name);
  p.type = ParamType::kBool;
  p.doc = std::move(doc);
  p.required = false;
  p.default_value = default_value;
  return p;
}

MachineTransition on_failed(std::string from, std::string to, std::string when = "") {
  MachineTransition t;
  t.from = std::move(from);
  t.on = MessageType::kFailed;
  t.to = std::move(to);
  t.when = std::move(when);
  return t;
}

MachineSpec pickup() {
  MachineSpec m;
  m.name = "pickup";
  m.doc =
      "reach for an object and grasp it, fixating on it with the head meanwhile; a grasp "
      "that does not hold is let go of and the next grasp reached for";
  m.params = {text_param("object", "object id in the perceptual model"),
              text_param("side", "arm to use; any: the free arm nearest the object", "any", kSides),
              flag_param("step", "step the base when arm and torso cannot reach", true),
              integer_param("attempts", "grasps to try before giving up", 3)};
  m.concurrent = {{"look", "fixate", {{"object", "$object"}, {"base", "false"}}, true}};
  m.states = {
      state(
          "reach", "reach",
          {{"object", "$object"}, {"side", "$side"}, {"base", "$step"}, {"attempts", "$attempts"}}),
      state("grasp", "grasp", {{"object", "$object"}, {"side", "$side"}}),
      // The grasp did not hold: open the hand, withdraw it, reach for the next grasp (reach
      // leaves out the grasps that failed, and fails once `attempts` have).
      state("let_go", "release", {{"side", "$side"}, {"near", "$object"}}),
      state("back_off", "retreat",
            {{"part", "hand"}, {"side", "$side"}, {"from", "$object"}, {"distance", "0.05"}}),
      final_state("held", true)};
  m.initial = "reach";
  m.transitions = {on_completed("reach", "grasp"),    on_completed("grasp", "held"),
                   on_failed("grasp", "let_go"),      on_completed("let_go", "back_off"),
                   on_completed("back_off", "reach"), on_failed("back_off", "reach")};
  m.transitions[1].stop = {"look"};
  return m;
}

MachineSpec putdown() {
  MachineSpec m;
  m.name = "putdown";
  m.doc = "place a held object resting on a surface, let go of it and bring the arms to rest";
  m.params = {text_param("object", "the held object"),
              text_param("surface", "surface to put it on", "work_surface")};
  // Let go, the hand rises straight off the object (open fingers round its far side would
  // drag it along if the hand drew back against its approach, or as the arm swings to rest),
  // the arms come to rest (and a bent torso upright): a hand left round what it set
  // down would sweep into the furniture as the base turns or steps, and hide the object from
  // the head camera. An arm whose hand still holds something stays as it is. Where the rest
  // fails (the rest posture puts an elbow into the furniture the robot stands against, or its
  // plan runs out of iterations), the robot steps back from the furniture and tries
  // once more; arms that still find no way stay where they are (the object is placed all the
  // same).
  const core::RawParams stow = {
      {"posture", "rest"}, {"chains", "[torso, left_arm, right_arm]"}, {"skip_busy", "true"}};
  m.states = {
      state("place", "position",
            {{"object", "$object"}, {"frame", "origin"}, {"on", "$surface"}, {"height", "0.01"}}),
      state("release", "release", {{"object", "$object"}}),
      state("clear", "retreat",
            {{"part", "hand"}, {"from", "$object"}, {"direction", "up"}, {"distance", "0.1"}}),
      state("stow", "postural", stow),
      state("make_room", "retreat", {{"part", "base"}, {"distance", "0.25"}}),
      state("stow_again", "postural", stow),
      final_state("placed", true)};
  m.initial = "place";
  m.transitions = {on_completed("place", "release"),        on_completed("release", "clear"),
                   on_completed("clear", "stow"),           on_failed("clear", "stow"),
                   on_completed("stow", "placed"),          on_failed("stow", "make_room"),
                   on_completed("make_room", "stow_again"), on_failed("make_room", "placed"),
                   on_completed("stow_again", "placed"),    on_failed("stow_again", "placed")};
  return m;
}

MachineSpec greet() {
  MachineSpec m;
  m.name = "greet";
  m.doc = "look at a person and, once they are in view, wave at them with a free arm";
  m.params = {text_param("target", "who to greet", "visitor"),
              text_param("side", "arm to wave with; any: a free one", "any", kSides)};
  // The base turns only while finding the target: the arms' plans (up to wave_start, down to
  // rest) assume it stays put, and so does the rest posture they end in.
  m.concurrent = {{"track", "fixate", {{"object", "$target"}, {"base", "false"}}, false}};
  // Close beside furniture (after a putdown), the base may not turn towards the target, nor
  // the arms come down to rest: the robot steps back from the furniture and tries once
  // more.
  const std::string limbs = "left_arm, right_arm, left_hand, right_hand";
  const core::RawParams lower = {
      {"posture", "rest"}, {"chains", "[" + limbs + "]"}, {"skip_busy", "true"}};
  // The second time with the torso: one bent by an earlier program (a putdown) puts the arms'
  // rest into the legs or the furniture.
  const core::RawParams lower_with_torso = {
      {"posture", "rest"}, {"chains", "[torso, " + limbs + "]"}, {"skip_busy", "true"}};
  const core::RawParams step_back = {{"part", "base"}, {"distance", "0.25"}};
  const core::RawParams find = {{"object", "$target"}, {"until_centered", "true"}};
  const core::RawParams raise = {{"posture", "wave_start"}, {"side", "$side"}};
  const core::RawParams wave = {{"motion", "wave"}, {"side", "$side"}};
  const std::string in_view = "in_view($target)";
  m.states = {state("find", "fixate", find), state("make_room", "retreat", step_back),
              // An arm left out over the furniture (after a putdown) sweeps into it as the
              // base turns: the arms come down (and a bent torso up) before finding again.
              state("tuck", "postural", lower_with_torso), state("find_again", "fixate", find),
              // Still wedged (between two pieces of furniture, the first step taken towards the
              // other): one more step back, from whatever is nearest now, and a last look.
              state("make_more_room", "retreat", step_back), state("find_last", "fixate", find),
              state("raise", "postural", raise, in_view), state("wave", "canned", wave, in_view),
              // The target walked out of view while the arm rose or waved: find it again
              // (the base turning too) and wave once more.
              state("find_raised", "fixate", find),
              // The arm found no way up with the target in view (wedged under or beside
              // furniture by a putdown: a shoulder below a table top, an arm over a counter):
              // a step back, the arms to rest (a lowered torso up), then find and raise again.
              state("make_room_to_raise", "retreat", step_back),
              state("tuck_to_raise", "postural", lower_with_torso),
              state("raise_again", "postural", raise, in_view),
              state("wave_again", "canned", wave, in_view), state("lower", "postural", lower),
              state("make_room_to_lower", "retreat", step_back),
              state("lower_again", "postural", lower_with_torso),
              // The arms down, the robot looks at the target again (it walked on while they
              // came down, untracked): turning the base is safe again. Not finding it does not
              // undo the greeting.
              state("look", "fixate", find), final_state("greeted", true)};
  m.initial = "find";
  m.transitions = {on_completed("find", "raise"),
                   on_completed("find_again", "raise"),
                   on_completed("raise", "wave"),
                   on_completed("wave", "lower"),
                   on_completed("lower", "look"),
                   on_completed("look", "greeted"),
                   on_failed("look", "greeted"),
                   on_failed("find", "make_room"),
                   on_completed("make_room", "tuck"),
                   on_completed("tuck", "find_again"),
                   on_failed("tuck", "find_again"),
                   on_failed("find_again", "make_more_room"),
                   on_completed("make_more_room", "find_last"),
                   on_completed("find_last", "raise"),
                   on_failed("lower", "make_room_to_lower"),
                   on_completed("make_room_to_lower", "lower_again"),
                   on_completed("lower_again", "look"),
                   on_failed("raise", "make_room_to_raise", in_view),
                   on_failed("raise", "find_raised"),
                   on_completed("make_room_to_raise", "tuck_to_raise"),
                   on_failed("make_room_to_raise", "tuck_to_raise"),
                   on_completed("tuck_to_raise", "find_raised"),
                   on_failed("tuck_to_raise", "find_raised"),
                   on_failed("wave", "find_raised"),
                   on_completed("find_raised", "raise_again"),
                   on_completed("raise_again", "wave_again"),
                   on_completed("wave_again", "lower")};
  for (MachineTransition& t : m.transitions) {
    // Tracking (the head alone) runs from the target found to the wave's end.
    if (t.on == MessageType::kCompleted && (t.to == "raise" || t.to == "raise_again")) {
      t.start = {"track"};
    }
    if ((t.on == MessageType::kCompleted && t.from.find("wave") == 0) || t.to == "find_raised") {
      t.stop = {"track"};
    }
  }
  return m;
}

MachineSpec vacuum() {
  MachineSpec m;
  m.name = "vacuum";
  m.doc = "pick up a vacuum, pass its tip over every known flake of debris, put it down";
  m.params = {text_param("tool", "the vacuum", "vacuum"),
              text_param("surface", "where to put the tool down afterwards", "work_surface")};
  m.states = {
      state("pickup", "pickup", {{"object", "$tool"}}),
      state("clean", "position",
            {{"object", "$tool"}, {"frame", "tip"}, {"target_type", "debris"}, {"height", "0.02"}}),
      state("putdown", "putdown", {{"object", "$tool"}, {"surface", "$surface"}}),
      final_state("clean_and_stowed", true)};
  m.initial = "pickup";
  m.transitions = {on_completed("pickup", "clean", "exists(debris)"),
                   on_completed("pickup", "putdown", "not(exists(debris))"),
                   on_completed("clean", "clean", "exists(debris)"),
                   on_completed("clean", "putdown", "not(exists(debris))"),
                   on_completed("putdown", "clean_and_stowed")};
  return m;
}

}  // namespace

void register_primitives(core::ProgramRegistry& registry) {
  registry.add(reach_program());
  registry.add(position_program());
  registry.add(grasp_program());
  registry.add(release_program());
  registry.add(fixate_program());
  registry.add(explore_program());
  registry.add(postural_program());
  registry.add(canned_program());
  registry.add(retreat_program());
}

void register_complex(core::ProgramRegistry& registry) {
  for (const MachineSpec& m : {pickup(), putdown(), greet(), vacuum()}) {
    core::register_machine(m, registry);
  }
}

void register_programs(core::ProgramRegistry& registry) {
  register_primitives(registry);
  register_complex(registry);
}

}  // namespace taskmatrix::programs
