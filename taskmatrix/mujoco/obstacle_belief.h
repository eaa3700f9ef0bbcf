// What queries know of a layout's obstacles. In ground-truth perception every obstacle of the
// layout; in sensor perception (set_need_perception) only the obstacle slots marked perceived.
// While a Scope is alive the worker's model hides the others from collision (their collision
// bits are cleared); the simulation always has every obstacle, so a plan through an unseen one
// ends in a collision during execution.
#pragma once

#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

class ObstacleBelief {
 public:
  explicit ObstacleBelief(const Scene& scene) : scene_(scene) { forget(); }

  // A layout with `count` obstacles (slots 0 .. count - 1) is applied; perceptions are forgotten.
  void set_active(int count);
  // Whether slot `slot` holds an obstacle of the applied layout.
  bool active(int slot) const { return slot >= 0 && slot < active_; }
  // Sensor mode: queries know an obstacle only once it is marked perceived. Forgets perceptions.
  void set_need_perception(bool need);
  void forget();  // no slot perceived
  // Throws std::invalid_argument for a slot the scene does not have.
  void mark_perceived(int slot);
  bool known(int slot) const { return active(slot) && (!need_perception_ || perceived_[slot]); }
  // Whether a Scope is alive (a query is running).
  bool in_scope() const { return depth_ > 0; }

  // While alive, `model` hides the obstacles queries do not know. Reentrant.
  class Scope {
   public:
    Scope(ObstacleBelief& belief, mjModel* model);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    ObstacleBelief& belief_;
    mjModel* model_;
  };

 private:
  const Scene& scene_;
  int active_ = 0;
  bool need_perception_ = false;
  std::vector<char> perceived_;  // per slot
  int depth_ = 0;
  struct HiddenGeom {
    int geom, contype, conaffinity;
  };
  std::vector<HiddenGeom> hidden_;  // what the outermost Scope cleared
};

}  // namespace taskmatrix::mujoco
