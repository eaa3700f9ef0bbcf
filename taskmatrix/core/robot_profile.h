// What a robot profile says about a robot, independent of how the robot is simulated: its
// kinematic chains, hands, head camera and named postures. Task programs see robots only
// through this description and the skillset; the MuJoCo backend checks it against the model.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace taskmatrix::core {

struct ChainSpec {
  std::string name;
  std::vector<std::string> joints;  // in kinematic order
  std::string end_effector;         // frame (site or body) at the chain's tip; may be empty
};

struct FingerSpec {
  std::vector<std::string> joints;  // from the palm outwards, one per segment
  std::vector<std::string> bodies;  // the segments, same order
};

struct HandSpec {
  std::string side;  // "left" or "right"
  std::string palm;  // frame (site or body) at the grasp centre
  // Unit axis, in the palm frame, pointing from the palm towards a grasped object: reach
  // brings the hand in along it.
  std::array<double, 3> approach{0, 0, 1};
  // Unit axis, in the palm frame and perpendicular to `approach`, along which the fingers
  // close on an object: reach prefers hand poses that keep it horizontal for upright objects.
  std::array<double, 3> closing{1, 0, 0};
  std::vector<FingerSpec> fingers;
};

// A predetermined joint-space motion (paper: canned task programs such as wave and bow):
// keyframes of the listed chains, played with linear interpolation between them.
struct CannedMotion {
  std::vector<std::string> chains;
  struct Keyframe {
    double time_s = 0;           // from the start of the motion, strictly increasing, first 0
    std::vector<double> values;  // the chains' joints, concatenated in the listed order
  };
  std::vector<Keyframe> keyframes;
};

// The head camera. For MJCF robots it is a <camera> in the model (only `name` is set); URDF
// cannot hold cameras, so a URDF robot's profile declares its pose and the loader adds it.
struct CameraSpec {
  std::string name;
  bool declared_in_profile = false;
  std::string body;
  std::array<double, 3> pos{0, 0, 0};
  std::array<double, 6> xyaxes{0, -1, 0, 0, 0, 1};
  double fovy_deg = 60.0;
};

// Execution limits of every joint of a chain: rad/s and rad/s^2 for hinges, m/s and m/s^2
// for slides.
struct SpeedLimit {
  double velocity = 0;
  double acceleration = 0;
};

// chain name -> joint values in the chain's joint order. Names only the chains it moves.
using Posture = std::map<std::string, std::vector<double>>;

enum class ModelFormat { kMjcf, kUrdf };

struct RobotProfile {
  std::string name;
  std::filesystem::path profile_file;
  std::filesystem::path model_file;
  ModelFormat format = ModelFormat::kMjcf;
  double height_m = 0.0;
  std::vector<ChainSpec> chains;
  CameraSpec head_camera;
  std::vector<HandSpec> hands;
  std::map<std::string, Posture> postures;
  std::map<std::string, SpeedLimit> speed_limits;  // chain name -> limits, one per chain
  // Mirroring a limb posture or motion to the other side ("left_arm" <-> "right_arm"): per
  // chain kind ("arm", "hand"), the sign each joint value takes on the other side.
  std::map<std::string, std::vector<double>> mirror_signs;
  std::map<std::string, CannedMotion> canned;
  // Position-actuator gains the URDF importer uses (chain name -> kp); MJCF robots carry
  // their own actuators.
  std::map<std::string, double> actuator_kp;

  const ChainSpec* find_chain(std::string_view chain_name) const;
  const HandSpec* find_hand(std::string_view side) const;
};

// The other side's chain of a limb chain ("left_arm" -> "right_arm"), or "" for a chain that
// has no side.
std::string mirror_chain(std::string_view chain);
// The chain kind mirror signs are keyed by: "left_arm" -> "arm"; "" for a chain with no side.
std::string chain_kind(std::string_view chain);

inline constexpr std::array<std::string_view, 5> kRequiredChains = {"base", "left_arm", "right_arm",
                                                                    "left_hand", "right_hand"};
// Chains the programs use when a robot has them: a robot with a rigid torso has no `torso`
// chain, and reach and position then go from the arm straight to a stance; a robot whose
// head camera is fixed has no `head` chain, and fixate and explore aim the camera with the
// base's yaw alone.
inline constexpr std::array<std::string_view, 2> kOptionalChains = {"torso", "head"};
// What the twelve task programs take from a profile by name (models/README.md, "What the
// programs need"): `rest` (every chain but the base; the start posture, release opens the
// hand to it, greet lowers the arms to it), `fist` (both hands; grasp closes towards it),
// `wave_start` (one side's arm: postural and greet raise it) and the canned motion `wave`
// (the same side's chains, starting at wave_start: canned and greet play it).
inline constexpr std::array<std::string_view, 3> kRequiredPostures = {"rest", "fist", "wave_start"};
inline constexpr std::array<std::string_view, 1> kRequiredCanned = {"wave"};

// Checks what can be checked without the model: required chains, postures and canned
// motions exist and name what the programs use of them, chains are disjoint, the base chain
// has three joints, postures name known chains with the right number of finite values, hands
// name their fingers consistently and have unit approach and closing axes, mirror signs fit
// the left/right chains, canned motions are well formed and within the chains' speed limits,
// `wave` starts at `wave_start`. Throws InputError naming the profile file and key. Every
// chain needs speed limits.
void validate_profile_structure(const RobotProfile& profile);

}  // namespace taskmatrix::core
