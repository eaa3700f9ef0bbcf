#include "taskmatrix/core/robot_profile.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::core {

const ChainSpec* RobotProfile::find_chain(std::string_view chain_name) const {
  for (const ChainSpec& c : chains) {
    if (c.name == chain_name) return &c;
  }
  return nullptr;
}

const HandSpec* RobotProfile::find_hand(std::string_view side) const {
  for (const HandSpec& h : hands) {
    if (h.side == side) return &h;
  }
  return nullptr;
}

std::string mirror_chain(std::string_view chain) {
  if (chain.substr(0, 5) == "left_") return "right_" + std::string(chain.substr(5));
  if (chain.substr(0, 6) == "right_") return "left_" + std::string(chain.substr(6));
  return "";
}

std::string chain_kind(std::string_view chain) {
  if (chain.substr(0, 5) == "left_") return std::string(chain.substr(5));
  if (chain.substr(0, 6) == "right_") return std::string(chain.substr(6));
  return "";
}

namespace {

void validate_mirroring(const RobotProfile& p, const std::string& file) {
  for (const ChainSpec& c : p.chains) {
    const std::string kind = chain_kind(c.name);
    if (kind.empty()) continue;
    const auto it = p.mirror_signs.find(kind);
    if (it == p.mirror_signs.end()) {
      throw InputError(file, "mirror_signs",
                       "has no entry '" + kind + "' for chain '" + c.name + "'");
    }
    if (it->second.size() != c.joints.size()) {
      throw InputError(file, "mirror_signs." + kind,
                       "has " + std::to_string(it->second.size()) + " signs but chain '" + c.name +
                           "' has " + std::to_string(c.joints.size()) + " joints");
    }
    if (!p.find_chain(mirror_chain(c.name))) {
      throw InputError(file, "chains",
                       "chain '" + c.name + "' has no mirror chain '" + mirror_chain(c.name) + "'");
    }
  }
  for (const auto& [kind, signs] : p.mirror_signs) {
    for (double s : signs) {
      if (s != 1.0 && s != -1.0) {
        throw InputError(file, "mirror_signs." + kind, "signs must be 1 or -1");
      }
    }
  }
}

void validate_canned(const RobotProfile& p, const std::string& file) {
  for (const auto& [name, motion] : p.canned) {
    const std::string key = "canned." + name;
    if (motion.chains.empty()) throw InputError(file, key + ".chains", "is empty");
    size_t dof = 0;
    std::vector<double> velocity;  // per joint
    for (const std::string& c : motion.chains) {
      const ChainSpec* chain = p.find_chain(c);
      if (!chain) throw InputError(file, key + ".chains", "names unknown chain '" + c + "'");
      dof += chain->joints.size();
      velocity.insert(velocity.end(), chain->joints.size(), p.speed_limits.at(c).velocity);
    }
    if (motion.keyframes.size() < 2) {
      throw InputError(file, key + ".keyframes", "needs at least two keyframes");
    }
    for (size_t k = 0; k < motion.keyframes.size(); ++k) {
      const CannedMotion::Keyframe& f = motion.keyframes[k];
      const std::string fkey = key + ".keyframes[" + std::to_string(k) + "]";
      if (f.values.size() != dof) {
        throw InputError(file, fkey,
                         "has " + std::to_string(f.values.size()) +
                             " joint values but the chains have " + std::to_string(dof) +
                             " joints (write [time, values...])");
      }
      for (double v : f.values) {
        if (!std::isfinite(v)) throw InputError(file, fkey, "holds a non-finite value");
      }
      if (k == 0 && f.time_s != 0.0) throw InputError(file, fkey, "must start at time 0");
      if (k == 0) continue;
      const CannedMotion::Keyframe& prev = motion.keyframes[k - 1];
      const double dt = f.time_s - prev.time_s;
      if (!(std::isfinite(f.time_s) && dt > 0)) {
        throw InputError(file, fkey, "time must be finite and later than the keyframe before");
      }
      for (size_t j = 0; j < dof; ++j) {
        const double v = std::abs(f.values[j] - prev.values[j]) / dt;
        if (v > velocity[j] * (1 + 1e-9)) {
          throw InputError(file, fkey,
                           "joint " + std::to_string(j) + " moves at " + std::to_string(v) +
                               " per second, above the speed limit " + std::to_string(velocity[j]) +
                               " of its chain");
        }
      }
    }
  }
}

// The side ("left"/"right") of the sided chains in `chains`, "" if there are none, "both"
// if they mix sides.
std::string side_of(const std::vector<std::string>& chains) {
  std::string side;
  for (const std::string& c : chains) {
    if (chain_kind(c).empty()) continue;
    const std::string s = c.substr(0, c.find('_'));
    if (!side.empty() && s != side) return "both";
    side = s;
  }
  return side;
}

// What the task programs use of the profile by name (kRequiredPostures, kRequiredCanned).
void validate_program_needs(const RobotProfile& p, const std::string& file) {
  const Posture& rest = p.postures.at("rest");
  std::vector<std::string_view> chains(kRequiredChains.begin(), kRequiredChains.end());
  for (std::string_view chain : kOptionalChains) {
    if (p.find_chain(chain)) chains.push_back(chain);
  }
  for (std::string_view chain : chains) {
    if (chain == "base" || rest.count(std::string(chain))) continue;
    throw InputError(file, "postures.rest",
                     "must name chain '" + std::string(chain) +
                         "' (the start posture; release and greet return limbs to rest)");
  }
  const Posture& fist = p.postures.at("fist");
  for (const char* hand : {"left_hand", "right_hand"}) {
    if (!fist.count(hand)) {
      throw InputError(file, "postures.fist",
                       std::string("must name chain '") + hand + "' (grasp closes towards it)");
    }
  }
  const Posture& wave_start = p.postures.at("wave_start");
  std::vector<std::string> raised;
  for (const auto& [chain, values] : wave_start) raised.push_back(chain);
  const std::string side = side_of(raised);
  if (side.empty() || side == "both" || !wave_start.count(side + "_arm")) {
    throw InputError(file, "postures.wave_start",
                     "must name one side's arm and no chain of the other side (greet mirrors "
                     "it to the free arm)");
  }
  const CannedMotion& wave = p.canned.at("wave");
  if (side_of(wave.chains) != side ||
      std::find(wave.chains.begin(), wave.chains.end(), side + "_arm") == wave.chains.end()) {
    throw InputError(file, "canned.wave.chains",
                     "must include '" + side +
                         "_arm' and no chain of the other side (greet "
                         "waves the arm it raised to wave_start)");
  }
  size_t offset = 0;
  for (const std::string& chain : wave.chains) {
    const size_t n = p.find_chain(chain)->joints.size();
    const auto it = wave_start.find(chain);
    if (it != wave_start.end()) {
      for (size_t i = 0; i < n; ++i) {
        if (std::abs(wave.keyframes[0].values[offset + i] - it->second[i]) > 1e-6) {
          throw InputError(file, "canned.wave.keyframes[0]",
                           "must equal postures.wave_start for chain '" + chain +
                               "' (greet plays the wave from the raised arm)");
        }
      }
    }
    offset += n;
  }
}

}  // namespace

void validate_profile_structure(const RobotProfile& p) {
  const std::string file = p.profile_file.string();
  for (std::string_view required : kRequiredChains) {
    if (!p.find_chain(required)) {
      throw InputError(file, "chains", "missing required chain '" + std::string(required) + "'");
    }
  }
  std::map<std::string, std::string> owner;  // joint -> chain
  for (const ChainSpec& c : p.chains) {
    if (c.joints.empty()) throw InputError(file, "chains." + c.name + ".joints", "is empty");
    for (const std::string& j : c.joints) {
      auto [it, inserted] = owner.emplace(j, c.name);
      if (!inserted) {
        throw InputError(
            file, "chains." + c.name + ".joints",
            "joint '" + j + "' is already in chain '" + it->second + "'; chains must be disjoint");
      }
    }
  }
  for (const ChainSpec& c : p.chains) {
    if (!p.speed_limits.count(c.name)) {
      throw InputError(file, "speed_limits", "has no entry for chain '" + c.name + "'");
    }
  }
  for (const auto& [chain_name, limit] : p.speed_limits) {
    const std::string key = "speed_limits." + chain_name;
    if (!p.find_chain(chain_name)) throw InputError(file, key, "names unknown chain");
    if (!(std::isfinite(limit.velocity) && limit.velocity > 0 &&
          std::isfinite(limit.acceleration) && limit.acceleration > 0)) {
      throw InputError(file, key, "velocity and acceleration must be positive and finite");
    }
  }
  if (p.find_chain("base")->joints.size() != 3) {
    throw InputError(file, "chains.base.joints",
                     "the base chain must have exactly three joints: a slide along x, a slide "
                     "along y and a hinge about z (a floating base's free joint is none of "
                     "them; models/README.md, 'A robot')");
  }
  for (std::string_view required : kRequiredPostures) {
    if (!p.postures.count(std::string(required))) {
      throw InputError(file, "postures",
                       "missing required posture '" + std::string(required) +
                           "' (the task programs use rest, fist and wave_start)");
    }
  }
  for (std::string_view required : kRequiredCanned) {
    if (!p.canned.count(std::string(required))) {
      throw InputError(file, "canned",
                       "missing required canned motion '" + std::string(required) +
                           "' (greet and the canned scenario play it)");
    }
  }
  for (const auto& [posture_name, posture] : p.postures) {
    for (const auto& [chain_name, values] : posture) {
      const std::string key = "postures." + posture_name + "." + chain_name;
      const ChainSpec* chain = p.find_chain(chain_name);
      if (!chain) throw InputError(file, key, "names unknown chain '" + chain_name + "'");
      if (values.size() != chain->joints.size()) {
        throw InputError(file, key,
                         "has " + std::to_string(values.size()) + " values but chain '" +
                             chain_name + "' has " + std::to_string(chain->joints.size()) +
                             " joints");
      }
      for (double v : values) {
        if (!std::isfinite(v)) throw InputError(file, key, "holds a non-finite value");
      }
    }
  }
  for (const char* side : {"left", "right"}) {
    if (!p.find_hand(side))
      throw InputError(file, "hands", std::string("missing the ") + side + " hand");
  }
  std::set<std::string> sides;
  for (const HandSpec& h : p.hands) {
    const std::string key = "hands." + h.side;
    if (h.side != "left" && h.side != "right") {
      throw InputError(file, key, "hand side must be 'left' or 'right'");
    }
    if (!sides.insert(h.side).second) throw InputError(file, key, "declared twice");
    if (h.palm.empty()) throw InputError(file, key + ".palm", "is missing");
    if (h.fingers.empty()) throw InputError(file, key + ".fingers", "is empty");
    const double norm = std::sqrt(h.approach[0] * h.approach[0] + h.approach[1] * h.approach[1] +
                                  h.approach[2] * h.approach[2]);
    if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-6) {
      throw InputError(file, key + ".approach", "must be a unit vector");
    }
    const double closing_norm = std::sqrt(
        h.closing[0] * h.closing[0] + h.closing[1] * h.closing[1] + h.closing[2] * h.closing[2]);
    const double dot =
        h.closing[0] * h.approach[0] + h.closing[1] * h.approach[1] + h.closing[2] * h.approach[2];
    if (!std::isfinite(closing_norm) || std::abs(closing_norm - 1.0) > 1e-6 ||
        std::abs(dot) > 1e-6) {
      throw InputError(file, key + ".closing", "must be a unit vector perpendicular to approach");
    }
    const ChainSpec* hand_chain = p.find_chain(h.side + "_hand");
    for (size_t f = 0; f < h.fingers.size(); ++f) {
      const FingerSpec& finger = h.fingers[f];
      const std::string fkey = key + ".fingers[" + std::to_string(f) + "]";
      if (finger.joints.empty() || finger.joints.size() != finger.bodies.size()) {
        throw InputError(file, fkey, "needs one body per joint (segments from the palm out)");
      }
      for (const std::string& j : finger.joints) {
        auto it = owner.find(j);
        if (it == owner.end() || it->second != hand_chain->name) {
          throw InputError(file, fkey + ".joints",
                           "joint '" + j + "' is not in chain '" + hand_chain->name + "'");
        }
      }
    }
  }
  if (!std::isfinite(p.height_m) || p.height_m <= 0.0) {
    throw InputError(file, "height_m", "must be a positive number of metres");
  }
  validate_mirroring(p, file);
  validate_canned(p, file);
  validate_program_needs(p, file);
}

}  // namespace taskmatrix::core
