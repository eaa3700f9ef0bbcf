// Collision verdicts for robot configurations: is the robot touching anything (itself, the
// world, obstacles, objects) at this configuration?
//
// `reference_robot_in_collision` is the reference: mj_kinematics + mj_collision on the whole
// model, the contacts MuJoCo's capsule-box function misses added (a capsule's axis inside a
// box), then "any contact with a robot geom". `ValidityChecker` gives the same verdicts faster:
//   - it knows which joints a query may move (the planned chains) and recomputes the poses
//     of only the bodies those joints move (hinge and slide joints, MuJoCo's own formulas);
//   - it tests only geom pairs that can change: at least one geom moved by those joints, the
//     pair allowed by MuJoCo's filters (contype/conaffinity, weld and parent, exclude);
//     pairs that cannot change are checked once, when the checker is bound to a state;
//   - a bounding-sphere test first, MuJoCo's narrow-phase function second, and it stops at
//     the first contact.
// Verdicts are identical to the reference; a test compares them on 100,000 configurations.
// Asked to (keep_off_visitor_route), it also counts the visitor's route as taken, which the raw
// check knows nothing of.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

// A task object held by the robot: it moves rigidly with `holder_body` and counts as part of
// the robot, except against `hand_bodies` (the hand holding it) and, within
// `support_tolerance_m` of penetration, against `support_geoms` (what it rested on when it
// was grasped, so lifting it off a table is not a collision).
struct Attachment {
  std::string object;    // the object's symbolic name (EnvironmentSpec::objects)
  std::string side;      // the hand holding it: "left" or "right"
  int body = -1;         // the object's root body: a child of the world with a free joint
  int holder_body = -1;  // robot body
  std::array<double, 3> pos{0, 0, 0};      // object frame in the holder's frame
  std::array<double, 4> quat{1, 0, 0, 0};  // w, x, y, z
  std::vector<int> hand_bodies;
  std::vector<int> support_geoms;
  double support_tolerance_m = 0.005;
};

// Writes the attached objects' free-joint qpos from their holders' poses in `d` (which must be
// current for the holders: after mj_kinematics) and zeroes their velocities.
void place_attachments(const mjModel* m, mjData* d, const std::vector<Attachment>& attachments);

// The robot's (and its held objects') contacts at the state in `d` (kinematics and collision
// are recomputed), as "a touches b (depth 1.2 mm); ...", at most three; "no contact" if none.
std::string describe_robot_contacts(const Scene& scene, const mjModel* m, mjData* d,
                                    const std::vector<Attachment>& attachments);
// True if contact `c` counts as a collision of the robot or what it holds: not a contact
// within one hand (Scene::same_hand), of a held object with its hand, or of a held object with
// what it rests on within the support tolerance.
bool counts_as_robot_collision(const Scene& scene, const mjModel* m, const mjContact& c,
                               const std::vector<Attachment>& attachments);

// The validity checker's test of one geom pair as posed in `d`, within `margin`: collision
// bits first, then bounding spheres (as MuJoCo's mj_collideGeoms), then, for a box, the other
// geom's bounding sphere against the box itself, then MuJoCo's narrow-phase function (a
// box-box pair's contacts no deeper than the boxes overlap along their normal: MuJoCo 2.2.2's
// box-box function reports phantom depths, correct_box_box_contacts in the .cc; a capsule-box
// pair's contact where MuJoCo reports none but the capsule's axis passes into the box,
// capsule_through_box in the .cc). Returns
// the number of contacts written to `out` (room for mjMAXCONPAIR), with their geom ids set;
// `narrow_calls`, if given, counts the narrow-phase calls.
int collide_geoms(const mjModel* m, mjData* d, const GeomPair& p, double margin, mjContact* out,
                  std::uint64_t* narrow_calls = nullptr);

// MuJoCo's own check on the worker's full model and data: runs mj_kinematics and
// mj_collision with data->qpos as it is (the raw baseline of the benchmarks).
// With attachments, their objects are first moved to their holders (mj_kinematics twice).
bool raw_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d,
                            const std::vector<Attachment>& attachments = {});

// The reference the checker's verdicts equal: raw_robot_in_collision, and a robot capsule
// whose axis passes into a box counts as touching it (MuJoCo 2.2.2's capsule-box function
// misses many such poses; collide_geoms adds the contact). describe_robot_contacts lists the
// same contacts.
bool reference_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d,
                                  const std::vector<Attachment>& attachments = {});

// The berth plans keep from the visitor's route beyond the visitor's own radius (m): a person
// walks it back and forth, and a plan made while they are elsewhere on it must not put the
// robot where they will be.
inline constexpr double kVisitorBerthM = 0.1;

class ValidityChecker {
 public:
  // `moving_joints`: MuJoCo joint ids the queries may change (hinge or slide robot joints).
  // Binds to the worker's current state (data->qpos): pairs that no moving joint can change
  // are evaluated once here, and the poses of bodies that do not move are taken from it.
  // `touch_geoms`: geoms the robot and what it holds may touch up to `touch_depth_m` of
  // penetration (what a plan may start against: the object a hand just let go of).
  ValidityChecker(const Scene& scene, const mjModel* m, mjData* d,
                  const std::vector<int>& moving_joints,
                  const std::vector<Attachment>& attachments = {},
                  const std::vector<int>& touch_geoms = {}, double touch_depth_m = 0);

  // True if the pairs that cannot change are already in contact at the bound state: then
  // every configuration is invalid (a start in collision with itself or the world).
  bool static_collision() const { return static_collision_; }
  // The deepest of those contacts (m; 0 when they only touch).
  double static_depth_m() const { return static_depth_m_; }
  // Leaves the pairs that cannot change as they are: configurations are judged by the pairs the
  // moving joints change (a hand resting against what it set down while the other arm moves;
  // execution, which checks what the moving chains touch, ignores them too).
  void accept_static_contacts();

  // Sets the moving joints' qpos to `values` (same order as moving_joints), updates the
  // moving bodies and geoms in `d`, and returns true if any robot geom is in contact.
  // `count`: whether this check adds to checks() (false when it follows within_margin on the
  // same state).
  bool in_collision(const double* values, bool count = true);
  // Like in_collision, but a robot-world pair also counts when MuJoCo finds it within
  // `margin_m` (beyond its own margin). Robot-robot pairs (a held object counts as the
  // robot's: against the hand's wrist or another held object it keeps no margin, as the arm's
  // own links keep none from each other) and pairs with a support tolerance (a held object on
  // what it rested on) are checked as in in_collision. `count` as there.
  bool within_margin(const double* values, double margin_m, bool count = true);

  // Keeps the robot off the visitor's route from now on: in_collision and within_margin count
  // a configuration as a collision where a geom the moving joints move (a held object's too)
  // comes within the visitor's radius (Scene::visitor_radius) plus `berth_m` of the route,
  // seen from above: the distance from the geom's centre to the nearest point of the route's
  // polyline, less how far the geom reaches from its centre that way (the box round it, seen
  // along that direction, at most its bounding radius). Geoms that close at the bound state
  // are left out: where the robot is, it may stay. Nothing changes in an environment without a
  // visitor route.
  void keep_off_visitor_route(double berth_m = kVisitorBerthM);
  // After a check that counted a collision: the geom found on the visitor's route, as
  // "'r_uarm' within 0.45 m of the visitor's route"; empty if the route was not what counted.
  std::string visitor_route_hit() const;

  // Smallest signed distance (m) between the geoms the moving joints move (attached objects
  // included) and everything they may touch, at `values`; capped at `cap_m`. Negative values
  // are MuJoCo's penetration depths; positive ones the smallest margin at which MuJoCo's
  // narrow phase reports a contact (to 0.01 mm). Penetration within an attachment's support
  // tolerance counts as distance 0.
  double distance(const double* values, double cap_m);
  // The same against the world only: the environment, its objects and obstacles, not the
  // floor and not the robot itself (held objects count as the robot's).
  double distance_to_world(const double* values, double cap_m);

  // Pairs that can change, grouped by the moving joints that change their relative pose: those
  // moving exactly one of the two geoms (a joint moving both moves them rigidly together). A
  // straight motion changing joint i by dq_i changes the distance of any pair of group g by at
  // most the sum over g's joints of joint_reach()[i] |dq_i|.
  // clearance_groups()[g][i]: whether moving joint i (moving_joints' order) is in group g.
  // Computed on first use (as is joint_reach()).
  const std::vector<std::vector<char>>& clearance_groups() {
    compute_clearance_groups();
    return clearance_groups_;
  }
  // Per group that `wanted` names (0 or 1 per group), how far (m) its pair closest to counting
  // as a contact is from it: the smallest distance by which MuJoCo's narrow phase would have to
  // come closer before in_collision counted the pair (its margin, or the penetration its
  // tolerance allows), capped at `cap_m`; `cap_m` for groups not wanted. Negative: in contact.
  // False when the bound state is in static collision (nothing measured). A check (adds to
  // checks()).
  bool clearances_to_contact(const double* values, double cap_m, const std::vector<char>& wanted,
                             std::vector<double>& clearances);
  // Per moving joint (moving_joints' order): the most any point of a geom it moves (held
  // objects included) can move per unit of it (m/rad or m/m), in any configuration: from the
  // model's body offsets, joint anchors, slide ranges and geom bounding radii.
  const std::vector<double>& joint_reach() {
    compute_clearance_groups();
    return joint_reach_;
  }

  std::uint64_t checks() const { return checks_; }
  size_t changing_pair_count() const { return changing_pairs_.size(); }
  std::uint64_t narrow_phase_calls() const { return narrow_calls_; }

 private:
  struct AttachedPair {
    GeomPair pair;
    double tolerance;        // allowed penetration
    bool with_world = true;  // the other geom is not the robot's nor held: planning margin
    int group = -1;          // index into clearance_groups_
  };
  // joint_reach_, clearance_groups_ and the pairs' groups, once.
  void compute_clearance_groups();
  // Per body: the farthest any point of a geom of its subtree (and of what it holds) can be
  // from its origin, in any configuration of the moving joints (0 for bodies that do not move).
  std::vector<double> subtree_reach() const;
  void set_values(const double* values);
  void update_moving_kinematics();
  void place_attached(const Attachment& a);
  // Counts the check and poses the moving joints at `values`; false if the robot is in static
  // collision (then every check is a collision and nothing else needs computing).
  bool begin_check(const double* values, bool count = true);
  // Number of contacts MuJoCo's narrow phase reports for the pair within `margin`, in scratch_.
  int collide(const GeomPair& p, double margin);
  bool pair_in_contact(const GeomPair& p, double tolerance = 0);
  // For a pair the moving joints cannot change: if it is in contact (as pair_in_contact with
  // `tolerance` judges), marks a static collision and keeps its deepest penetration.
  void note_static_contact(const GeomPair& p, double tolerance);
  double pair_distance(const GeomPair& p, double cap);

  const Scene& scene_;
  const mjModel* m_;
  mjData* d_;
  std::vector<int> joints_;
  std::vector<int> qpos_adr_;
  std::vector<int> moving_bodies_;  // in increasing id order: parents first
  std::vector<int> moving_geoms_;
  std::vector<GeomPair> changing_pairs_;
  std::vector<char> changing_pair_with_world_;   // per changing pair: one geom is not the robot's
  std::vector<double> changing_pair_tolerance_;  // per changing pair: allowed penetration
  std::vector<int> changing_pair_group_;         // per changing pair: its clearance group
  std::vector<double> joint_reach_;
  std::vector<std::vector<char>> clearance_groups_;
  std::vector<char> moving_;    // per body: moved by the moving joints
  std::vector<int> object_of_;  // per body: the attachment whose object it belongs to, or -1
  // The changing pairs as the checks visit them: pairs of a moving body's geoms with the geoms
  // of one body that does not move are grouped, and a group whose two bounding spheres (the
  // moving body's about its origin, the other body's fixed for the checker's life) are farther
  // apart than its largest margin is skipped whole, as each of its pairs' own bounding-sphere
  // test would skip it. The other pairs (both bodies moving, a plane) are visited one by one.
  struct PairGroup {
    int moving_body = -1;
    double fixed_center[3] = {0, 0, 0};
    double radius = 0;        // both spheres' radii
    double margin = 0;        // the largest pair margin
    bool with_world = false;  // some pair gets the planning margin
    std::vector<int> pairs;   // indices into changing_pairs_
  };
  std::vector<int> ungrouped_pairs_;
  std::vector<PairGroup> pair_groups_;
  int pair_visits_ = 0;  // visits of the changing pairs, counted to 2: grouped from the second
  // Needs the bound state's poses: the fixed geoms', and the moving geoms' offsets from their
  // bodies (either configuration serves: the offsets are rigid).
  void group_changing_pairs();
  // Whether the group's spheres come within its margin plus `extra` (if it has world pairs,
  // or for any group with `extra_for_all`).
  bool group_near(const PairGroup& group, double extra, bool extra_for_all = false) const;
  // Visits the changing pairs; true as soon as `hit(k)` is for pair k. `extra`: the planning
  // margin world pairs get (every pair with `extra_for_all`).
  template <class Hit>
  bool any_changing_pair(double extra, Hit hit, bool extra_for_all = false);
  // True (and route_hit_ set) if a route geom is on the visitor's route at the posed state.
  bool on_visitor_route();
  // Whether geom `g` (as posed in d_) comes within route_radius_ of the route.
  bool geom_on_route(int g) const;
  // Distance (m, seen from above) from `c` to the route's polyline; `away`: from its nearest
  // point to `c`.
  double distance_to_route(const Eigen::Vector2d& c, Eigen::Vector2d* away = nullptr) const;
  std::vector<double> bound_values_;    // the moving joints' values at the bound state
  std::vector<Eigen::Vector2d> route_;  // the visitor's path (world x, y), if kept off
  double route_radius_ = 0;             // the visitor's radius plus the berth
  // The geoms kept off it, grouped under the topmost moving body above them, which is skipped
  // whole while its origin is farther from the route than the radius plus its subtree's reach.
  struct RouteGroup {
    int root = -1;
    double reach = 0;
    std::vector<int> geoms;
  };
  std::vector<RouteGroup> route_groups_;
  int route_hit_ = -1;  // the geom the last check found on it
  std::vector<Attachment> attachments_;
  std::vector<size_t> moving_attachments_;    // indices into attachments_
  std::vector<AttachedPair> attached_pairs_;  // pairs that move with moving attachments
  bool static_collision_ = false;
  double static_depth_m_ = 0;
  std::uint64_t checks_ = 0;
  std::uint64_t narrow_calls_ = 0;
  mjContact scratch_[mjMAXCONPAIR];
};

}  // namespace taskmatrix::mujoco
