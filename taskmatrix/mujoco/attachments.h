// The objects the robot's hands hold: one Attachment (validity_checker.h) per held object,
// with its name and the hand holding it, in the order they were grasped.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

// The geoms that are not the robot's and touch object `body` (a root body) in `d`'s contacts.
std::vector<int> supports_of(const mjModel* m, const mjData* d, const Scene& scene, int body);

// `object` (root body `body`, a free body) held by robot body `holder_body` of the hand on
// `side`, keeping their relative pose in `d` (current: after mj_forward); its supports are
// what it touches in `d`.
Attachment attachment_at(const Scene& scene, const mjModel* m, const mjData* d, int body,
                         int holder_body, std::string object, std::string side);

class HeldObjects {
 public:
  const std::vector<Attachment>& list() const { return held_; }
  bool empty() const { return held_.empty(); }
  // The attachment of `object`, or nullptr when it is not held.
  const Attachment* find(std::string_view object) const;
  // Whether the object with root body `body` is held.
  bool holds_body(int body) const;
  void add(Attachment attachment) { held_.push_back(std::move(attachment)); }
  // Lets go of `object`; its root body, or -1 if it was not held.
  int remove(std::string_view object);
  void clear() { held_.clear(); }
  std::vector<std::string> objects() const;
  // Adds to each held object's supports what it touches in `d` (besides its hand): the surface
  // a plan lifts it from is what it rests on when the plan starts, not only when it was grasped.
  void refresh_supports(const Scene& scene, const mjModel* m, const mjData* d);

 private:
  std::vector<Attachment> held_;
};

}  // namespace taskmatrix::mujoco
