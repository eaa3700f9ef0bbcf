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

Eigen::AlignedBox3d Shape::bounds() const {
  Eigen::Vector3d half;
  for (int i = 0; i < 3; ++i) half[i] = half_width(Eigen::Vector3d::Unit(i));
  return {pose.position - half, pose.position + half};
}

std::vector<size_t> protruding_shapes(const PerceivedObject& object) {
  std::vector<size_t> out;
  const std::vector<Shape>& shapes = object.shapes;
  if (shapes.size() < 2) return out;
  // The far side of `shapes` (all but `skip`) along `u`.
  auto reach = [&](const Eigen::Vector3d& u, size_t skip) {
    double far = -INFINITY;
    for (size_t j = 0; j < shapes.size(); ++j) {
      if (j != skip) far = std::max(far, shapes[j].pose.position.dot(u) + shapes[j].half_width(u));
    }
    return far;
  };
  Eigen::AlignedBox3d all(shapes.front().bounds());
  for (const Shape& s : shapes) all.extend(s.bounds());
  const Eigen::Vector3d centre = all.center();
  for (size_t i = 0; i < shapes.size(); ++i) {
    Eigen::Vector3d out_dir = shapes[i].pose.position - centre;
    out_dir.z() = 0;
    if (out_dir.norm() < 1e-9) continue;
    out_dir.normalize();
    const double part = shapes[i].pose.position.dot(out_dir) + shapes[i].half_width(out_dir);
    if (part > reach(out_dir, i) + kProtrudingPartM) out.push_back(i);
  }
  return out;
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
