#include "taskmatrix/core/conditions.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace taskmatrix::core {

namespace {

constexpr double kAboveTolerance = 0.02;
constexpr double kGraspableDistance = 0.03;

std::optional<Eigen::AlignedBox3d> box_of(const World& world, const std::string& id,
                                          const Hypothesis* h) {
  if (h && h->id == id) return h->box;
  const PerceivedObject* o = world.percepts.find(id);
  if (!o) return std::nullopt;
  return o->box;
}

// A box of `a`'s size resting on `b`'s top face, its centre drawn uniformly so that it lies
// within `b`'s footprint grown by `grow` (or anywhere over the footprint if it does not fit).
Eigen::AlignedBox3d resting_on(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b,
                               double grow, std::mt19937_64& rng) {
  const Eigen::Vector3d half = a.sizes() / 2;
  Eigen::Vector3d centre(0, 0, b.max().z() + half.z());
  for (int i = 0; i < 2; ++i) {
    double lo = b.min()[i] - grow + half[i], hi = b.max()[i] + grow - half[i];
    if (lo > hi) lo = b.min()[i], hi = b.max()[i];
    centre[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return Eigen::AlignedBox3d(centre - half, centre + half);
}

class Near final : public Condition {
 public:
  Near(std::string a, std::string b, double d) : a_(std::move(a)), b_(std::move(b)), d_(d) {}
  bool holds(const World& w, const Hypothesis* h) const override {
    const auto a = box_of(w, a_, h), b = box_of(w, b_, h);
    return a && b && box_distance(*a, *b) <= d_;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "near(" << a_ << ", " << b_ << ", " << d_ << ")";
    return s.str();
  }
  // On top of b, anywhere within d of its footprint.
  std::optional<Eigen::AlignedBox3d> propose(const World& w, const std::string& object,
                                             std::mt19937_64& rng) const override {
    if (object != a_) return std::nullopt;
    const auto a = box_of(w, a_, nullptr), b = box_of(w, b_, nullptr);
    if (!a || !b) return std::nullopt;
    return resting_on(*a, *b, d_, rng);
  }

 private:
  std::string a_, b_;
  double d_;
};

class Above final : public Condition {
 public:
  Above(std::string a, std::string b) : a_(std::move(a)), b_(std::move(b)) {}
  bool holds(const World& w, const Hypothesis* h) const override {
    const auto a = box_of(w, a_, h), b = box_of(w, b_, h);
    if (!a || !b) return false;
    const bool overlap_xy = a->min().x() <= b->max().x() && b->min().x() <= a->max().x() &&
                            a->min().y() <= b->max().y() && b->min().y() <= a->max().y();
    return overlap_xy && a->min().z() >= b->max().z() - kAboveTolerance;
  }
  std::string describe() const override { return "above(" + a_ + ", " + b_ + ")"; }
  // Resting on b's top face, wholly inside its footprint when it fits.
  std::optional<Eigen::AlignedBox3d> propose(const World& w, const std::string& object,
                                             std::mt19937_64& rng) const override {
    if (object != a_) return std::nullopt;
    const auto a = box_of(w, a_, nullptr), b = box_of(w, b_, nullptr);
    if (!a || !b) return std::nullopt;
    return resting_on(*a, *b, 0.0, rng);
  }

 private:
  std::string a_, b_;
};

class Postural final : public Condition {
 public:
  Postural(std::string posture, std::vector<std::string> chains, double tol)
      : posture_(std::move(posture)), chains_(std::move(chains)), tol_(tol) {}
  bool holds(const World& w, const Hypothesis*) const override {
    const Posture& p = w.skills.posture(posture_);
    for (const auto& [chain, values] : p) {
      if (!chains_.empty() && std::find(chains_.begin(), chains_.end(), chain) == chains_.end())
        continue;
      const std::vector<double> q = w.skills.configuration({chain});
      for (size_t i = 0; i < q.size(); ++i) {
        if (std::abs(q[i] - values[i]) > tol_) return false;
      }
    }
    return true;
  }
  std::string describe() const override {
    std::string s = "postural(" + posture_;
    for (const std::string& c : chains_) s += ", " + c;
    return s + ")";
  }

 private:
  std::string posture_;
  std::vector<std::string> chains_;
  double tol_;
};

class Grasping final : public Condition {
 public:
  explicit Grasping(std::string a) : a_(std::move(a)) {}
  bool holds(const World& w, const Hypothesis*) const override {
    return !w.skills.holder_of(a_).empty();
  }
  std::string describe() const override { return "grasping(" + a_ + ")"; }

 private:
  std::string a_;
};

class Graspable final : public Condition {
 public:
  Graspable(std::string a, std::string side) : a_(std::move(a)), side_(std::move(side)) {}
  bool holds(const World& w, const Hypothesis* h) const override {
    const auto box = box_of(w, a_, h);
    if (!box || !w.skills.holder_of(a_).empty()) return false;
    const PerceivedObject* known = w.percepts.find(a_);
    const Eigen::Vector3d grasp_point =
        (h && h->id == a_) || !known ? box->center() : known->grasp_point();
    for (const HandSpec& hand : w.skills.profile().hands) {
      if (side_ != "any" && hand.side != side_) continue;
      const Pose palm = w.skills.frame_pose(hand.palm);
      if ((palm.position - grasp_point).norm() <= kGraspableDistance) return true;
    }
    return false;
  }
  std::string describe() const override { return "graspable(" + a_ + ", " + side_ + ")"; }

 private:
  std::string a_, side_;
};

class Junction final : public Condition {
 public:
  Junction(std::vector<ConditionPtr> c, bool all) : c_(std::move(c)), all_(all) {}
  bool holds(const World& w, const Hypothesis* h) const override {
    for (const ConditionPtr& c : c_) {
      if (c->holds(w, h) != all_) return !all_;
    }
    return all_;
  }
  std::string describe() const override {
    std::string s = all_ ? "all_of(" : "any_of(";
    for (size_t i = 0; i < c_.size(); ++i) s += (i ? ", " : "") + c_[i]->describe();
    return s + ")";
  }
  std::optional<Eigen::AlignedBox3d> propose(const World& w, const std::string& object,
                                             std::mt19937_64& rng) const override {
    for (const ConditionPtr& c : c_) {
      std::optional<Eigen::AlignedBox3d> box = c->propose(w, object, rng);
      if (!box) continue;
      const Hypothesis h{object, *box};
      if (holds(w, &h)) return box;
      return std::nullopt;  // a draw that failed the other members
    }
    return std::nullopt;
  }

 private:
  std::vector<ConditionPtr> c_;
  bool all_;
};

class Not final : public Condition {
 public:
  explicit Not(ConditionPtr c) : c_(std::move(c)) {}
  bool holds(const World& w, const Hypothesis* h) const override { return !c_->holds(w, h); }
  std::string describe() const override { return "not(" + c_->describe() + ")"; }

 private:
  ConditionPtr c_;
};

}  // namespace

std::optional<Eigen::AlignedBox3d> Condition::propose(const World&, const std::string&,
                                                      std::mt19937_64&) const {
  return std::nullopt;
}

ConditionPtr near(std::string a, std::string b, double distance_m) {
  return std::make_shared<Near>(std::move(a), std::move(b), distance_m);
}
ConditionPtr above(std::string a, std::string b) {
  return std::make_shared<Above>(std::move(a), std::move(b));
}
ConditionPtr postural(std::string posture, std::vector<std::string> chains, double tolerance) {
  return std::make_shared<Postural>(std::move(posture), std::move(chains), tolerance);
}
ConditionPtr grasping(std::string object) { return std::make_shared<Grasping>(std::move(object)); }
ConditionPtr graspable(std::string object, std::string side) {
  return std::make_shared<Graspable>(std::move(object), std::move(side));
}
ConditionPtr all_of(std::vector<ConditionPtr> conditions) {
  return std::make_shared<Junction>(std::move(conditions), true);
}
ConditionPtr any_of(std::vector<ConditionPtr> conditions) {
  return std::make_shared<Junction>(std::move(conditions), false);
}
ConditionPtr negate(ConditionPtr condition) { return std::make_shared<Not>(std::move(condition)); }

std::vector<Eigen::AlignedBox3d> sample_placements(const Condition& condition, const World& world,
                                                   const std::string& object, std::mt19937_64& rng,
                                                   int count, int max_draws) {
  std::vector<Eigen::AlignedBox3d> out;
  for (int draw = 0; draw < max_draws && static_cast<int>(out.size()) < count; ++draw) {
    const std::optional<Eigen::AlignedBox3d> box = condition.propose(world, object, rng);
    if (!box) continue;
    const Hypothesis h{object, *box};
    if (condition.holds(world, &h)) out.push_back(*box);
  }
  return out;
}

double box_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  Eigen::Vector3d gap = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    gap[i] = std::max({0.0, a.min()[i] - b.max()[i], b.min()[i] - a.max()[i]});
  }
  return gap.norm();
}

}  // namespace taskmatrix::core
