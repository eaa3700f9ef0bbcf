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

Eigen::Vector2d SurfaceTop::local(const Eigen::Vector2d& p) const {
  if (!turned()) return p;
  return {cos * p.x() + sin * p.y(), -sin * p.x() + cos * p.y()};
}

Eigen::Vector2d SurfaceTop::world(const Eigen::Vector2d& l) const {
  if (!turned()) return l;
  return {cos * l.x() - sin * l.y(), sin * l.x() + cos * l.y()};
}

Eigen::Vector2d SurfaceTop::extent(const Eigen::Vector2d& half) const {
  if (!turned()) return half;
  const double c = std::abs(cos), s = std::abs(sin);
  return {c * half.x() + s * half.y(), s * half.x() + c * half.y()};
}

double SurfaceTop::signed_distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d q = local(p);
  const Eigen::Vector2d out = (lo - q).cwiseMax(q - hi);  // > 0 along an axis: outside
  return out.maxCoeff() <= 0 ? out.maxCoeff() : out.cwiseMax(0).norm();
}

Eigen::Vector2d SurfaceTop::nearest(const Eigen::Vector2d& p) const {
  return world(local(p).cwiseMax(lo).cwiseMin(hi));
}

bool SurfaceTop::overlaps(const Eigen::Vector2d& box_lo, const Eigen::Vector2d& box_hi) const {
  if (!turned()) {
    return box_lo.x() <= hi.x() && lo.x() <= box_hi.x() && box_lo.y() <= hi.y() &&
           lo.y() <= box_hi.y();
  }
  // Separating axes: the top's two and the world's two.
  const Eigen::Vector2d centre = local((box_lo + box_hi) / 2);
  const Eigen::Vector2d half = extent((box_hi - box_lo) / 2);
  if (centre.x() - half.x() > hi.x() || centre.x() + half.x() < lo.x() ||
      centre.y() - half.y() > hi.y() || centre.y() + half.y() < lo.y()) {
    return false;
  }
  Eigen::AlignedBox2d bounds;  // the top's world-aligned bounds
  for (int corner = 0; corner < 4; ++corner) {
    bounds.extend(world({corner & 1 ? hi.x() : lo.x(), corner & 2 ? hi.y() : lo.y()}));
  }
  return box_lo.x() <= bounds.max().x() && bounds.min().x() <= box_hi.x() &&
         box_lo.y() <= bounds.max().y() && bounds.min().y() <= box_hi.y();
}

Eigen::AlignedBox2d SurfaceTop::inscribed() const {
  if (!turned()) return {lo, hi};
  // A world-aligned rectangle of half extents (w, h) centred in the top (half extents a, b)
  // fits where c w + s h <= a and s w + c h <= b. The largest: where both bind, or the best
  // point on one line that keeps within the other; the top's world bounds scaled down to fit
  // always do.
  const double a = (hi.x() - lo.x()) / 2, b = (hi.y() - lo.y()) / 2;
  const double c = std::abs(cos), s = std::abs(sin);
  auto fits = [&](double w, double h) {
    return w >= 0 && h >= 0 && c * w + s * h <= a * (1 + 1e-9) && s * w + c * h <= b * (1 + 1e-9);
  };
  const double bw = c * a + s * b, bh = s * a + c * b;
  const double k = std::min(a / (c * bw + s * bh), b / (s * bw + c * bh));
  double w = k * bw, h = k * bh;
  auto consider = [&](double cw, double ch) {
    if (std::isfinite(cw) && std::isfinite(ch) && fits(cw, ch) && cw * ch > w * h) w = cw, h = ch;
  };
  const double det = c * c - s * s;
  if (std::abs(det) > 1e-9) consider((a * c - b * s) / det, (b * c - a * s) / det);
  if (c > 0 && s > 0) {
    consider(a / (2 * c), a / (2 * s));
    consider(b / (2 * s), b / (2 * c));
  }
  const Eigen::Vector2d centre = world((lo + hi) / 2);
  return {centre - Eigen::Vector2d(w, h), centre + Eigen::Vector2d(w, h)};
}

SurfaceTop surface_top(const Eigen::AlignedBox3d& box, const Pose& pose,
                       const Eigen::AlignedBox2d& top) {
  SurfaceTop out;
  out.height = box.isEmpty() ? pose.position.z() : box.max().z();
  const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
  const double n = std::hypot(r(0, 0), r(1, 0));
  if (top.isEmpty() || n < 1e-9 || (r(1, 0) == 0 && r(0, 0) > 0)) {
    out.lo = box.min().head<2>();
    out.hi = box.max().head<2>();
    return out;
  }
  out.cos = r(0, 0) / n;
  out.sin = r(1, 0) / n;
  const Eigen::Vector2d origin = out.local(pose.position.head<2>());
  out.lo = origin + top.min();
  out.hi = origin + top.max();
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
