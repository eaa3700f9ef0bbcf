#include "taskmatrix/mujoco/obstacle_belief.h"

#include <stdexcept>
#include <string>

namespace taskmatrix::mujoco {

void ObstacleBelief::set_active(int count) {
  active_ = count;
  forget();
}

void ObstacleBelief::set_need_perception(bool need) {
  need_perception_ = need;
  forget();
}

void ObstacleBelief::forget() { perceived_.assign(scene_.obstacle_slots().size(), 0); }

void ObstacleBelief::mark_perceived(int slot) {
  if (slot < 0 || slot >= static_cast<int>(perceived_.size())) {
    throw std::invalid_argument("no obstacle slot " + std::to_string(slot));
  }
  perceived_[slot] = 1;
}

ObstacleBelief::Scope::Scope(ObstacleBelief& belief, mjModel* model)
    : belief_(belief), model_(model) {
  if (belief_.depth_ == 0 && belief_.need_perception_) {
    const std::vector<ObstacleSlot>& slots = belief_.scene_.obstacle_slots();
    belief_.hidden_.clear();
    for (int slot = 0; slot < belief_.active_; ++slot) {
      if (belief_.perceived_[slot]) continue;
      for (int g : slots[slot].geoms) {
        belief_.hidden_.push_back({g, model_->geom_contype[g], model_->geom_conaffinity[g]});
        model_->geom_contype[g] = 0;
        model_->geom_conaffinity[g] = 0;
      }
    }
  }
  ++belief_.depth_;
}

ObstacleBelief::Scope::~Scope() {
  if (--belief_.depth_ > 0) return;
  for (const HiddenGeom& h : belief_.hidden_) {
    model_->geom_contype[h.geom] = h.contype;
    model_->geom_conaffinity[h.geom] = h.conaffinity;
  }
  belief_.hidden_.clear();
}

}  // namespace taskmatrix::mujoco
