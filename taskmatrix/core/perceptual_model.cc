#include "taskmatrix/core/perceptual_model.h"

namespace taskmatrix::core {

void PerceptualModel::observe(PerceivedObject object) {
  std::string id = object.id;
  objects_.insert_or_assign(std::move(id), std::move(object));
}

void PerceptualModel::forget(std::string_view id) {
  const auto it = objects_.find(id);
  if (it != objects_.end()) objects_.erase(it);
}

const PerceivedObject* PerceptualModel::find(std::string_view id) const {
  const auto it = objects_.find(id);
  return it == objects_.end() ? nullptr : &it->second;
}

std::vector<const PerceivedObject*> PerceptualModel::of_type(std::string_view type) const {
  std::vector<const PerceivedObject*> out;
  for (const auto& [id, object] : objects_) {
    if (object.type == type) out.push_back(&object);
  }
  return out;
}

}  // namespace taskmatrix::core
