#include "taskmatrix/mujoco/kinematics.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <random>
#include <stdexcept>

#include "taskmatrix/mujoco/body_kinematics.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

namespace {

// A pose from a position and a rotation matrix (MuJoCo's xpos and xmat).
core::Pose pose_from_matrix(const mjtNum* pos, const mjtNum* mat) {
  core::Pose pose;
  pose.position = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  Eigen::Matrix3d r;
  r << mat[0], mat[1], mat[2], mat[3], mat[4], mat[5], mat[6], mat[7], mat[8];
  pose.orientation = Eigen::Quaterniond(r).normalized();
  return pose;
}

core::Pose compose(const core::Pose& body, const core::Pose& offset) {
  core::Pose pose;
  pose.position = body.position + body.orientation * offset.position;
  pose.orientation = (body.orientation * offset.orientation).normalized();
  return pose;
}

}  // namespace

core::Pose frame_pose(const mjData* d, FrameRef frame) {
  const double* pos = frame.kind == FrameRef::Kind::kSite   ? d->site_xpos + 3 * frame.id
                      : frame.kind == FrameRef::Kind::kBody ? d->xpos + 3 * frame.id
                                                            : d->cam_xpos + 3 * frame.id;
  const double* mat = frame.kind == FrameRef::Kind::kSite   ? d->site_xmat + 9 * frame.id
                      : frame.kind == FrameRef::Kind::kBody ? d->xmat + 9 * frame.id
                                                            : d->cam_xmat + 9 * frame.id;
  return pose_from_matrix(pos, mat);
}

core::Pose frame_pose(const mjData* d, const BodyFrame& frame) {
  return compose(pose_from_matrix(d->xpos + 3 * frame.body, d->xmat + 9 * frame.body),
                 frame.offset);
}

ChainPath::ChainPath(const mjModel* m, const std::vector<int>& joints, int frame_body,
                     bool from_world)
    : m_(m) {
  std::vector<int> up;
  for (int b = frame_body; b > 0; b = m->body_parentid[b]) up.push_back(b);
  std::reverse(up.begin(), up.end());
  std::vector<char> listed(m->njnt, 0);
  for (int j : joints) listed[j] = 1;
  size_t first = from_world ? 0 : up.size();
  for (size_t k = 0; k < up.size() && first == up.size(); ++k) {
    for (int i = 0; i < m->body_jntnum[up[k]]; ++i) {
      if (listed[m->body_jntadr[up[k]] + i]) first = k;
    }
  }
  bodies_.assign(up.begin() + static_cast<long>(first), up.end());
  top_parent_ = bodies_.empty() ? frame_body : m->body_parentid[bodies_.front()];
  frame_of_joint_.assign(m->njnt, -1);
  for (int b : bodies_) {
    posable_ = posable_ && m->body_mocapid[b] < 0;
    for (int i = 0; i < m->body_jntnum[b]; ++i) {
      const int type = m->jnt_type[m->body_jntadr[b] + i];
      posable_ = posable_ && (type == mjJNT_HINGE || type == mjJNT_SLIDE);
      frame_of_joint_[m->body_jntadr[b] + i] = static_cast<int>(joint_frames_.size());
      joint_frames_.push_back({});
    }
  }
  pos_.resize(3 * bodies_.size());
  quat_.resize(4 * bodies_.size());
  mat_.resize(9 * bodies_.size());
  inputs_.resize(joint_frames_.size());
}

core::Pose ChainPath::update(const mjData* d, const mjtNum* qpos) {
  if (!qpos) qpos = d->qpos;
  const mjtNum* ppos = d->xpos + 3 * top_parent_;
  const mjtNum* pquat = d->xquat + 4 * top_parent_;
  const mjtNum* pmat = d->xmat + 9 * top_parent_;
  // The leading bodies whose inputs (the pose above the path, their joints' values) are bit
  // for bit those of the last update keep their poses: a joint held still (a base placed by a
  // stance search) costs nothing per iteration.
  mjtNum top[16];
  std::copy(ppos, ppos + 3, top);
  std::copy(pquat, pquat + 4, top + 3);
  std::copy(pmat, pmat + 9, top + 7);
  bool same = updated_ && std::memcmp(top, top_, sizeof top) == 0;
  std::copy(top, top + 16, top_);
  updated_ = true;
  JointFrame* frames = joint_frames_.data();
  mjtNum* inputs = inputs_.data();
  for (size_t k = 0; k < bodies_.size(); ++k) {
    const int b = bodies_[k];
    const int nj = m_->body_jntnum[b];
    for (int i = 0; i < nj; ++i) {
      const mjtNum v = qpos[m_->jnt_qposadr[m_->body_jntadr[b] + i]];
      same = same && std::memcmp(&v, &inputs[i], sizeof v) == 0;
      inputs[i] = v;
    }
    inputs += nj;
    if (!same) {
      body_pose_from_parent(m_, qpos, b, ppos, pquat, pmat, &pos_[3 * k], &quat_[4 * k],
                            &mat_[9 * k], frames);
    }
    frames += nj;
    ppos = &pos_[3 * k];
    pquat = &quat_[4 * k];
    pmat = &mat_[9 * k];
  }
  frame_pos_ = ppos;
  frame_mat_ = pmat;
  core::Pose pose;
  pose.position = Eigen::Vector3d(ppos[0], ppos[1], ppos[2]);
  pose.orientation = Eigen::Quaterniond(pquat[0], pquat[1], pquat[2], pquat[3]);
  return pose;
}

core::Pose ChainPath::frame_pose(const core::Pose& offset) const {
  return compose(pose_from_matrix(frame_pos_, frame_mat_), offset);
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
  mj_kinematics(worker.model(), worker.data());  // a simulation step moves qpos on
  return solve_ik(scene, worker.model(), worker.data(), joints, frame, target, options);
}

namespace {

Eigen::Vector3d vec3(const mjtNum* v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

// What a start must improve its error by within IkOptions::stall_iterations to go on.
constexpr double kStallFraction = 0.01;
// Random starts sample slide joints within this much more than the frame's distance to the
// target of their current value (a base need not move farther than the hand must).
constexpr double kSlideSlackM = 0.5;

}  // namespace

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
  std::vector<int> adr(n);
  Eigen::VectorXd lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    const int j = joints[i];
    if (j < 0 || j >= m->njnt || (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE)) {
      return finish(core::IkStatus::kInvalidInput,
                    "joint id " + std::to_string(j) + " is not a hinge or slide");
    }
    adr[i] = m->jnt_qposadr[j];
    lo[i] = m->jnt_range[2 * j];
    hi[i] = m->jnt_range[2 * j + 1];
  }
  const std::vector<double> saved(d->qpos, d->qpos + m->nq);
  // The bodies above the chain are read from d's kinematics (current for its qpos, the
  // contract). The iterations write only the chain's qpos, which is restored; only the
  // collision checker changes d's poses, and then they are recomputed at the end.
  ChainPath path(m, joints, frame.body);
  // Collision checks only for converged solutions: the checker is made on the first.
  std::optional<ValidityChecker> checker;

  if ((!o.start.empty() && o.start.size() != static_cast<size_t>(n)) ||
      (!o.joint_weights.empty() && o.joint_weights.size() != static_cast<size_t>(n))) {
    return finish(
        core::IkStatus::kInvalidInput,
        "the IK start and joint weights need one value per joint (" + std::to_string(n) + ")");
  }
  Eigen::VectorXd current(n);
  for (int i = 0; i < n; ++i) {
    current[i] = std::clamp(o.start.empty() ? saved[adr[i]] : o.start[i], lo[i], hi[i]);
  }
  // Weighted damped least squares: a joint of weight zero keeps its start value.
  const bool weighted = !o.joint_weights.empty();
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(n);
  for (int i = 0; weighted && i < n; ++i) weight[i] = o.joint_weights[i];
  auto moves = [&](int i) { return path.on_path(joints[i]) && weight[i] > 0; };
  auto frame_at = [&](const Eigen::VectorXd& q) {
    for (int i = 0; i < n; ++i) d->qpos[adr[i]] = q[i];
    return compose(path.update(d), frame.offset);
  };
  const core::Pose pose_now = frame_at(current);

  // Out of reach: with hinges only, the frame stays within the sum of the distances between
  // successive joint anchors (and from the last one to the frame) of the first anchor.
  std::vector<int> path_joints;  // listed joints that move the frame, from the root outwards
  for (int j = 0; j < m->njnt; ++j) {
    const auto listed = std::find(joints.begin(), joints.end(), j);
    if (listed != joints.end() && moves(static_cast<int>(listed - joints.begin()))) {
      path_joints.push_back(j);
    }
  }
  const bool hinges_only = std::all_of(path_joints.begin(), path_joints.end(),
                                       [&](int j) { return m->jnt_type[j] == mjJNT_HINGE; });
  if (hinges_only) {
    double reach = 0;
    Eigen::Vector3d origin = pose_now.position;
    if (!path_joints.empty()) {
      for (size_t k = 0; k + 1 < path_joints.size(); ++k) {
        reach +=
            (vec3(path.joint(path_joints[k + 1]).anchor) - vec3(path.joint(path_joints[k]).anchor))
                .norm();
      }
      reach += (pose_now.position - vec3(path.joint(path_joints.back()).anchor)).norm();
      origin = vec3(path.joint(path_joints.front()).anchor);
    }
    const double needed = (target.position - origin).norm();
    if (needed > reach + o.position_tolerance_m) {
      std::copy(saved.begin(), saved.end(), d->qpos);
      result.position_error_m = needed - reach;
      result.orientation_error_rad = 0;
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "out of reach: the target is %.3f m from the chain's first joint, which "
                    "reaches %.3f m",
                    needed, reach);
      return finish(core::IkStatus::kUnreachable, buf);
    }
  }

  // Where random starts are drawn: each joint's limits, slide joints only as far from their
  // current value as the frame is from the target (plus slack), and widening from the current
  // configuration over the first half of the restarts.
  Eigen::VectorXd sample_lo = lo, sample_hi = hi;
  const double span = (target.position - pose_now.position).norm() + kSlideSlackM;
  for (int i = 0; i < n; ++i) {
    if (m->jnt_type[joints[i]] != mjJNT_SLIDE) continue;
    sample_lo[i] = std::max(lo[i], current[i] - span);
    sample_hi[i] = std::min(hi[i], current[i] + span);
  }

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int rows = o.orientation ? 6 : 3;
  double best_pos = INFINITY, best_rot = INFINITY;
  int converged_in_collision = 0;
  std::string first_contact;
  Eigen::MatrixXd jac(rows, n);
  Eigen::VectorXd err(rows);
  // The step's work space, allocated once: an iteration allocates nothing.
  Eigen::MatrixXd jw(rows, n), jjt(rows, rows);
  Eigen::LDLT<Eigen::MatrixXd> ldlt(rows);
  Eigen::VectorXd y(rows), dq(n);

  for (int attempt = 0;
       attempt <= o.restarts && static_cast<int>(result.solutions.size()) < o.max_solutions;
       ++attempt) {
    Eigen::VectorXd q = current;
    if (attempt > 0) {
      const double widen =
          std::min(1.0, 2.0 * attempt / static_cast<double>(std::max(1, o.restarts)));
      for (int i = 0; i < n; ++i) {
        const double u = unit(rng);  // drawn for every joint: the stream does not depend on n
        if (!moves(i)) continue;
        const double a = current[i] - widen * (current[i] - sample_lo[i]);
        const double b = current[i] + widen * (sample_hi[i] - current[i]);
        q[i] = a + (b - a) * u;
      }
    }
    double lambda = 0.05;
    double start_best = INFINITY;
    int last_improvement = 0;
    for (int it = 0; it < o.max_iterations; ++it) {
      ++result.iterations;
      const core::Pose now = frame_at(q);
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
        if (o.collision_free) {
          if (!checker) {
            // Bound to the state the query started from.
            std::copy(saved.begin(), saved.end(), d->qpos);
            checker.emplace(scene, m, d, joints, attachments);
            checker->keep_off_visitor_route();
          }
          if (checker->in_collision(solution.data())) {
            if (converged_in_collision++ == 0) {
              // What the first one touches, for the reason: its first contact.
              for (int i = 0; i < n; ++i) d->qpos[adr[i]] = solution[i];
              first_contact = checker->visitor_route_hit();
              if (first_contact.empty()) {
                first_contact = describe_robot_contacts(scene, m, d, attachments);
              }
              first_contact = first_contact.substr(0, first_contact.find(';'));
            }
            break;
          }
        }
        result.solutions.push_back(solution);
        break;
      }
      if (pos_err + rot_err < (1.0 - kStallFraction) * start_best) {
        start_best = pos_err + rot_err;
        last_improvement = it;
      } else if (o.stall_iterations > 0 && it - last_improvement >= o.stall_iterations) {
        break;
      }
      // The Jacobian of the frame's origin and orientation, column by column.
      for (int i = 0; i < n; ++i) {
        const int j = joints[i];
        if (!path.on_path(j)) {
          jac.col(i).setZero();
          continue;
        }
        const JointFrame& f = path.joint(j);
        const Eigen::Vector3d axis = vec3(f.axis);
        if (m->jnt_type[j] == mjJNT_SLIDE) {
          jac.col(i).head<3>() = axis;
          if (o.orientation) jac.col(i).tail<3>().setZero();
        } else {
          jac.col(i).head<3>() = axis.cross(now.position - vec3(f.anchor));
          if (o.orientation) jac.col(i).tail<3>() = axis;
        }
      }
      if (o.orientation && free_axis) jac.bottomRows<3>() = keep * jac.bottomRows<3>();
      // dq = Jw^T (J Jw^T + lambda^2 I)^-1 err, Jw = J diag(weight) (J itself unweighted).
      if (weighted) jw.noalias() = jac * weight.asDiagonal();
      const Eigen::MatrixXd& jl = weighted ? jw : jac;
      jjt.noalias() = jl * jac.transpose();
      jjt.diagonal().array() += lambda * lambda;
      ldlt.compute(jjt);
      y = ldlt.solve(err);
      dq.noalias() = jl.transpose() * y;
      const double step = dq.cwiseAbs().maxCoeff();
      if (step > 0.3) dq *= 0.3 / step;  // keep steps in the linear regime
      q = (q + dq).cwiseMax(lo).cwiseMin(hi);
    }
  }
  std::copy(saved.begin(), saved.end(), d->qpos);
  if (checker) {  // it posed the chain (and held objects' geoms) in d: restore the poses
    mj_kinematics(m, d);
    if (!attachments.empty()) {
      place_attachments(m, d, attachments);
      mj_kinematics(m, d);
    }
  }
  result.position_error_m = best_pos;
  result.orientation_error_rad = best_rot;
  if (!result.solutions.empty()) return finish(core::IkStatus::kSolved, "");
  if (converged_in_collision > 0) {
    return finish(core::IkStatus::kInCollision,
                  std::to_string(converged_in_collision) +
                      " solutions found, all in collision (first: " + first_contact + ")");
  }
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "no solution within limits from %d starts (best: %.1f mm, %.2f deg)",
                o.restarts + 1, best_pos * 1e3, best_rot * 180 / M_PI);
  return finish(core::IkStatus::kUnreachable, buf);
}

}  // namespace taskmatrix::mujoco
