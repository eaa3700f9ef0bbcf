#include "taskmatrix/programs/program_support.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace taskmatrix::programs {

std::string arm_of(const std::string& side) { return side + "_arm"; }
std::string hand_of(const std::string& side) { return side + "_hand"; }

std::vector<std::string> free_sides(const core::ClaimContext& ctx,
                                    const std::vector<std::string>& sides,
                                    std::string (*chain_of)(const std::string&)) {
  std::vector<std::string> out;
  for (const std::string& s : sides) {
    if (!ctx.busy(chain_of(s))) out.push_back(s);
  }
  return out;
}

std::string nearest_free_side(const core::ClaimContext& ctx, const std::string& object,
                              std::string (*chain_of)(const std::string&)) {
  const std::vector<std::string> free = free_sides(ctx, {"left", "right"}, chain_of);
  if (free.empty()) return "left";
  const core::PerceivedObject* o = ctx.percepts.find(object);
  if (!o) return free.front();
  std::string best = free.front();
  double best_distance = INFINITY;
  for (const std::string& side : free) {
    const core::HandSpec* hand = ctx.skills.profile().find_hand(side);
    const double d = (ctx.skills.frame_pose(hand->palm).position - o->grasp_point()).norm();
    if (d < best_distance) {
      best_distance = d;
      best = side;
    }
  }
  return best;
}

std::string single_side(const std::vector<std::string>& chains) {
  std::string side;
  for (const std::string& c : chains) {
    if (core::chain_kind(c).empty()) continue;
    const std::string s = c.substr(0, c.find('_'));
    if (!side.empty() && s != side) return "";
    side = s;
  }
  return side;
}

ChainValues mirrored(const core::Skillset& skills, const ChainValues& v) {
  ChainValues out;
  size_t offset = 0;
  for (const std::string& c : v.chains) {
    const size_t n = skills.chain(c).joints.size();
    const std::string other = core::mirror_chain(c);
    out.chains.push_back(other.empty() ? c : other);
    const std::vector<double>* signs = nullptr;
    if (!other.empty()) signs = &skills.profile().mirror_signs.at(core::chain_kind(c));
    for (size_t i = 0; i < n; ++i) {
      out.values.push_back(signs ? (*signs)[i] * v.values[offset + i] : v.values[offset + i]);
    }
    offset += n;
  }
  return out;
}

ChainValues posture_values(const core::Skillset& skills, const std::string& posture,
                           const std::vector<std::string>& only_chains) {
  const core::Posture& p = skills.posture(posture);
  for (const std::string& c : only_chains) {
    skills.chain(c);  // throws for an unknown chain
    if (!p.count(c)) {
      throw std::invalid_argument("posture '" + posture + "' does not name chain '" + c + "'");
    }
  }
  ChainValues out;
  for (const auto& [chain, values] : p) {
    if (!only_chains.empty() &&
        std::find(only_chains.begin(), only_chains.end(), chain) == only_chains.end()) {
      continue;
    }
    out.chains.push_back(chain);
    out.values.insert(out.values.end(), values.begin(), values.end());
  }
  return out;
}

std::vector<double> clamped_configuration(const core::Skillset& skills,
                                          const std::vector<std::string>& chains) {
  return skills.clamped_configuration(chains);
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}

LimbChoice choose_limb(const core::ClaimContext& ctx, const ChainValues& named,
                       const std::string& side) {
  const std::string named_side = single_side(named.chains);
  if (side == "as_named" || named_side.empty()) return {false};
  if (side != "any") return {side != named_side};
  const ChainValues other = mirrored(ctx.skills, named);
  auto busy = [&](const ChainValues& v) {
    return std::any_of(v.chains.begin(), v.chains.end(), ctx.busy);
  };
  const bool named_busy = busy(named), other_busy = busy(other);
  if (named_busy != other_busy) return {named_busy};
  auto there = [&](const ChainValues& v) {
    return max_difference(ctx.skills.configuration(v.chains), v.values) <= kAlreadyThere;
  };
  const bool named_there = there(named), other_there = there(other);
  if (named_there != other_there) return {other_there};
  std::mt19937 rng(ctx.seed);
  return {std::bernoulli_distribution(0.5)(rng)};
}

std::string plan_failure_reason(const core::PlanResult& plan) {
  return std::string(core::to_string(plan.status)) + ": " + plan.message;
}

std::string MotionStage::plan_to_configuration(core::ProgramContext& ctx,
                                               const std::vector<std::string>& chains,
                                               const std::vector<double>& goal) {
  core::PlanOptions options = ctx.plan_options();
  options.seed = ctx.next_seed();
  ctx.emit(core::MessageType::kPlanningStarted);
  auto plan = std::make_shared<const core::PlanResult>(
      ctx.skills().plan_to_configuration(chains, goal, options));
  return start_following(ctx, chains, std::move(plan));
}

std::string MotionStage::plan_to_poses(core::ProgramContext& ctx,
                                       const std::vector<std::string>& chains,
                                       const std::string& frame,
                                       const std::vector<core::Pose>& poses,
                                       const core::IkOptions& ik) {
  core::PlanOptions options = ctx.plan_options();
  options.seed = ctx.next_seed();
  core::IkOptions ik_options = ik;
  ik_options.seed = options.seed;
  ctx.emit(core::MessageType::kPlanningStarted);
  auto plan = std::make_shared<const core::PlanResult>(
      ctx.skills().plan_to_poses(chains, frame, poses, options, ik_options));
  return start_following(ctx, chains, std::move(plan));
}

std::string ArmMotion::reach_from_here(core::ProgramContext& ctx) {
  std::string failure = motion_.plan_to_poses(ctx, {arm_}, frame_, poses_, ik_);
  if (torso_ && failure.rfind("ik_failure", 0) == 0) {
    failure = motion_.plan_to_poses(ctx, {"torso", arm_}, frame_, poses_, ik_);
  }
  return failure;
}

std::string ArmMotion::start(core::ProgramContext& ctx, const std::string& arm,
                             const std::string& frame, std::vector<core::Pose> poses,
                             const core::IkOptions& ik, bool torso, bool base) {
  arm_ = arm;
  frame_ = frame;
  poses_ = std::move(poses);
  ik_ = ik;
  torso_ = torso;
  stepping_ = false;
  const std::string failure = reach_from_here(ctx);
  if (!base || failure.rfind("ik_failure", 0) != 0) return failure;
  // Step: a stance from which the arm reaches, found by IK over the whole body.
  core::Skillset& skills = ctx.skills();
  std::vector<std::string> body{"base"};
  if (torso_) body.push_back("torso");
  body.push_back(arm_);
  core::IkOptions whole = ik_;
  whole.seed = ctx.next_seed();
  std::string why;
  for (size_t k = 0; k < poses_.size(); ++k) {
    const core::IkResult r = skills.solve_ik(body, frame_, poses_[k], whole);
    if (r.solutions.empty()) {
      if (why.empty()) why = r.reason;
      continue;
    }
    // The base alone when the arm can stay as it is at the new stance; else the whole body.
    const std::vector<double>& solution = r.solutions.front();
    const size_t nb = skills.chain("base").joints.size();
    std::vector<double> stance_now = skills.configuration(body);
    std::copy(solution.begin(), solution.begin() + static_cast<long>(nb), stance_now.begin());
    if (skills.is_valid(body, stance_now)) {
      const std::vector<double> stance(solution.begin(), solution.begin() + static_cast<long>(nb));
      const std::string moved = motion_.plan_to_configuration(ctx, {"base"}, stance);
      if (!moved.empty()) return moved;
      stepping_ = true;
      return "";
    }
    return motion_.plan_to_configuration(ctx, body, solution);
  }
  return failure + "; stepping: no stance found (" + why + ")";
}

std::optional<std::string> ArmMotion::step(core::ProgramContext& ctx) {
  const std::optional<std::string> result = motion_.step();
  if (!result || !result->empty() || !stepping_) return result;
  stepping_ = false;
  const std::string failure = reach_from_here(ctx);
  if (!failure.empty()) return failure;
  return std::nullopt;
}

std::vector<std::string> arm_claim(const core::ClaimContext& ctx, const std::string& arm,
                                   bool& torso, bool& base) {
  torso = torso && !ctx.busy("torso");
  base = base && !ctx.busy("base");
  std::vector<std::string> chains;
  if (base) chains.push_back("base");
  if (torso) chains.push_back("torso");
  chains.push_back(arm);
  return chains;
}

std::vector<std::string> head_claim(const core::ClaimContext& ctx, bool& base) {
  base = base && !ctx.busy("base");
  if (base) return {"head", "base"};
  return {"head"};
}

std::string MotionStage::start_following(core::ProgramContext& ctx,
                                         const std::vector<std::string>& chains,
                                         std::shared_ptr<const core::PlanResult> plan) {
  plan_ = plan;
  const std::string reason = plan->success() ? "" : plan_failure_reason(*plan);
  ctx.emit(core::MessageType::kPlanningEnded, reason, plan);
  if (!plan->success()) return reason;
  follow(ctx, chains, core::timed(ctx.skills().time_parameterize(chains, plan->path)), execution);
  return "";
}

void MotionStage::follow(core::ProgramContext& ctx, const std::vector<std::string>& chains,
                         core::TimedMotion motion, const core::ExecutionOptions& options) {
  follower_.emplace(ctx.skills(), chains, std::move(motion), options);
}

std::optional<std::string> MotionStage::step() {
  if (!follower_) return std::string("invalid_input: no motion to follow");
  const std::optional<core::ExecutionReport> done = follower_->step();
  if (!done) return std::nullopt;
  follower_.reset();
  if (done->success()) return std::string();
  return std::string(core::to_string(done->status)) + ": " + done->message;
}

}  // namespace taskmatrix::programs
