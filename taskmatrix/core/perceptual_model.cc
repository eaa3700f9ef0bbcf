#include "taskmatrix/core/perceptual_model.h"

#include <algorithm>
#include <cmath>

namespace taskmatrix::core {

double Shape::half_width(const Eigen::Vector3d& u) const {
  const Eigen::Vector3d local = pose.orientation.conjugate() * u;
  switch (type) {
    case Type::kBox:
      return local.cwiseAbs().dot(size);
    case Type::kSphere:
      return size.x();
    case Type::kCapsule:
      return size.x() + std::abs(local.z()) * size.y();
    case Type::kCylinder:
      return size.x() * std::sqrt(std::max(0.0, 1 - local.z() * local.z())) +
             std::abs(local.z()) * size.y();
    case Type::kEllipsoid:
      return local.cwiseProduct(size).norm();
  }
  return 0;
}

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
