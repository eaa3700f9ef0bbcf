#include "taskmatrix/mujoco/kinematics.h"

#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>

#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

core::Pose frame_pose(const mjData* d, FrameRef frame) {
  core::Pose pose;
  const double* pos = frame.kind == FrameRef::Kind::kSite   ? d->site_xpos + 3 * frame.id
                      : frame.kind == FrameRef::Kind::kBody ? d->xpos + 3 * frame.id
                                                            : d->cam_xpos + 3 * frame.id;
  const double* mat = frame.kind == FrameRef::Kind::kSite   ? d->site_xmat + 9 * frame.id
                      : frame.kind == FrameRef::Kind::kBody ? d->xmat + 9 * frame.id
                                                            : d->cam_xmat + 9 * frame.id;
  pose.position = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  Eigen::Matrix3d r;
  r << mat[0], mat[1], mat[2], mat[3], mat[4], mat[5], mat[6], mat[7], mat[8];
  pose.orientation = Eigen::Quaterniond(r).normalized();
  return pose;
}

core::Pose frame_pose(const mjData* d, const BodyFrame& frame) {
  const core::Pose body = frame_pose(d, FrameRef{FrameRef::Kind::kBody, frame.body});
  core::Pose pose;
  pose.position = body.position + body.orientation * frame.offset.position;
  pose.orientation = (body.orientation * frame.offset.orientation).normalized();
  return pose;
}

BodyFrame resolve_frame(const Scene& scene, const mjData* d, const std::string& name,
                        const std::vector<Attachment>& attachments) {
  const mjModel* m = scene.model();
  const FrameRef ref = scene.frame(name);
  BodyFrame frame;
  if (ref.kind == FrameRef::Kind::kSite) {
    frame.body = m->site_bodyid[ref.id];
    const double* p = m->site_pos + 3 * ref.id;
    const double* q = m->site_quat + 4 * ref.id;
    frame.offset.position = Eigen::Vector3d(p[0], p[1], p[2]);
    frame.offset.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  } else if (ref.kind == FrameRef::Kind::kCamera) {
    frame.body = m->cam_bodyid[ref.id];
    const double* p = m->cam_pos + 3 * ref.id;
    const double* q = m->cam_quat + 4 * ref.id;
    frame.offset.position = Eigen::Vector3d(p[0], p[1], p[2]);
    frame.offset.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  } else {
    frame.body = ref.id;
  }
  for (const Attachment& a : attachments) {
    if (m->body_rootid[frame.body] != a.body) continue;
    // On a held object: re-express the frame on the holder, from the current poses.
    const core::Pose world = frame_pose(d, frame);
    const core::Pose holder = frame_pose(d, FrameRef{FrameRef::Kind::kBody, a.holder_body});
    frame.body = a.holder_body;
    frame.offset.position = holder.orientation.conjugate() * (world.position - holder.position);
    frame.offset.orientation = (holder.orientation.conjugate() * world.orientation).normalized();
  }
  return frame;
}

namespace {

// Rotation taking `current` to `target`, as an axis times angle in the world frame.
Eigen::Vector3d orientation_error(const Eigen::Quaterniond& target,
                                  const Eigen::Quaterniond& current) {
  Eigen::Quaterniond diff = target * current.conjugate();
  if (diff.w() < 0) diff.coeffs() *= -1;
  const Eigen::AngleAxisd aa(diff);
  return aa.axis() * aa.angle();
}

}  // namespace

core::IkResult solve_ik(const Scene& scene, WorkerScene& worker, const std::vector<int>& joints,
                        const std::string& frame, const core::Pose& target,
                        const IkOptions& options) {
  return solve_ik(scene, worker.model(), worker.data(), joints, frame, target, options);
}

core::IkResult solve_ik(const Scene& scene, const mjModel* m, mjData* d,
                        const std::vector<int>& joints, const std::string& frame_name,
                        const core::Pose& target, const IkOptions& o,
                        const std::vector<Attachment>& attachments) {
  const auto t0 = std::chrono::steady_clock::now();
  core::IkResult result;
  auto finish = [&](core::IkStatus status, std::string reason) {
    result.status = status;
    result.reason = std::move(reason);
    result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };
  if (!target.position.allFinite() || !target.orientation.coeffs().allFinite() ||
      std::abs(target.orientation.norm() - 1.0) > 1e-6) {
    return finish(core::IkStatus::kInvalidInput,
                  "target pose is not finite or its quaternion is not unit length");
  }
  if (joints.empty()) return finish(core::IkStatus::kInvalidInput, "no joints to solve for");
  std::optional<Eigen::Vector3d> free_axis;
  if (o.free_axis.squaredNorm() > 0) {
    if (!o.free_axis.allFinite() || std::abs(o.free_axis.norm() - 1.0) > 1e-6) {
      return finish(core::IkStatus::kInvalidInput, "the free axis must be a unit vector");
    }
    free_axis = o.free_axis;
  }
  BodyFrame frame;
  try {
    frame = resolve_frame(scene, d, frame_name, attachments);
  } catch (const std::out_of_range& e) {
    return finish(core::IkStatus::kInvalidInput, e.what());
  }
  const int n = static_cast<int>(joints.size());
  std::vector<int> adr(n), dof(n);
  Eigen::VectorXd lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    const int j = joints[i];
    if (j < 0 || j >= m->njnt || (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE)) {
      return finish(core::IkStatus::kInvalidInput,
                    "joint id " + std::to_string(j) + " is not a hinge or slide");
    }
    adr[i] = m->jnt_qposadr[j];
    dof[i] = m->jnt_dofadr[j];
    lo[i] = m->jnt_range[2 * j];
    hi[i] = m->jnt_range[2 * j + 1];
  }
  const std::vector<double> saved(d->qpos, d->qpos + m->nq);
  ValidityChecker checker(scene, m, d, joints, attachments);

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> jacp(3 * m->nv), jacr(3 * m->nv);
  const int rows = o.orientation ? 6 : 3;
  double best_pos = INFINITY, best_rot = INFINITY;
  int converged_in_collision = 0;

  for (int attempt = 0;
       attempt <= o.restarts && static_cast<int>(result.solutions.size()) < o.max_solutions;
       ++attempt) {
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q[i] = attempt == 0 ? std::clamp(saved[adr[i]], lo[i], hi[i])
                          : lo[i] + (hi[i] - lo[i]) * unit(rng);
    }
    double lambda = 0.05;
    for (int it = 0; it < o.max_iterations; ++it) {
      ++result.iterations;
      for (int i = 0; i < n; ++i) d->qpos[adr[i]] = q[i];
      mj_kinematics(m, d);
      mj_comPos(m, d);
      const core::Pose now = frame_pose(d, frame);
      const double point[3] = {now.position.x(), now.position.y(), now.position.z()};
      Eigen::VectorXd err(rows);
      err.head<3>() = target.position - now.position;
      // Rotation about the free axis (in world coordinates now) is not an error.
      Eigen::Matrix3d keep = Eigen::Matrix3d::Identity();
      if (free_axis) {
        const Eigen::Vector3d a = now.orientation * *free_axis;
        keep -= a * a.transpose();
      }
      if (o.orientation) {
        err.tail<3>() = keep * orientation_error(target.orientation, now.orientation);
      }
      const double pos_err = err.head<3>().norm();
      const double rot_err = o.orientation ? err.tail<3>().norm() : 0.0;
      if (pos_err + rot_err < best_pos + best_rot) {
        best_pos = pos_err;
        best_rot = rot_err;
      }
      if (pos_err <= o.position_tolerance_m && rot_err <= o.orientation_tolerance_rad) {
        std::vector<double> solution(q.data(), q.data() + n);
        bool distinct = true;
        for (const auto& s : result.solutions) {
          double dmax = 0;
          for (int i = 0; i < n; ++i) dmax = std::max(dmax, std::abs(s[i] - solution[i]));
          distinct = distinct && dmax > o.distinct_rad;
        }
        if (!distinct) break;
        if (o.collision_free && checker.in_collision(solution.data())) {
          ++converged_in_collision;
          break;
        }
        result.solutions.push_back(solution);
        break;
      }
      mj_jac(m, d, jacp.data(), o.orientation ? jacr.data() : nullptr, point, frame.body);
      Eigen::MatrixXd jac(rows, n);
      for (int i = 0; i < n; ++i) {
        for (int r = 0; r < 3; ++r) {
          jac(r, i) = jacp[r * m->nv + dof[i]];
          if (o.orientation) jac(3 + r, i) = jacr[r * m->nv + dof[i]];
        }
      }
      if (o.orientation && free_axis) jac.bottomRows<3>() = keep * jac.bottomRows<3>();
      const Eigen::MatrixXd jjt =
          jac * jac.transpose() + lambda * lambda * Eigen::MatrixXd::Identity(rows, rows);
      Eigen::VectorXd dq = jac.transpose() * jjt.ldlt().solve(err);
      const double step = dq.cwiseAbs().maxCoeff();
      if (step > 0.3) dq *= 0.3 / step;  // keep steps in the linear regime
      q = (q + dq).cwiseMax(lo).cwiseMin(hi);
    }
  }
  std::copy(saved.begin(), saved.end(), d->qpos);
  mj_kinematics(m, d);
  if (!attachments.empty()) {  // the checker moved held objects' geoms; restore their poses
    place_attachments(m, d, attachments);
    mj_kinematics(m, d);
  }
  result.position_error_m = best_pos;
  result.orientation_error_rad = best_rot;
  if (!result.solutions.empty()) return finish(core::IkStatus::kSolved, "");
  if (converged_in_collision > 0) {
    return finish(core::IkStatus::kInCollision,
                  std::to_string(converged_in_collision) + " solutions found, all in collision");
  }
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "no solution within limits from %d starts (best: %.1f mm, %.2f deg)",
                o.restarts + 1, best_pos * 1e3, best_rot * 180 / M_PI);
  return finish(core::IkStatus::kUnreachable, buf);
}

}  // namespace taskmatrix::mujoco
