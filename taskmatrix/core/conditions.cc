#include "taskmatrix/core/conditions.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace taskmatrix::core {

namespace {

constexpr double kAboveTolerance = 0.02;
constexpr double kGraspableDistance = 0.03;

std::string cm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f cm", metres * 100);
  return buf;
}

// Which of `ids` the perceptual model does not know.
std::string unknown(const World& w, const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) {
    if (!w.percepts.find(id)) out += (out.empty() ? "" : " and ") + id;
  }
  return out + " unknown to the perceptual model";
}

std::optional<Eigen::AlignedBox3d> box_of(const World& world, const std::string& id,
                                          const Hypothesis* h) {
  if (h && h->id == id) return h->box;
  const PerceivedObject* o = world.percepts.find(id);
  if (!o) return std::nullopt;
  return o->box;
}

// The top of `id` seen from above: a surface's top face (turned with the surface), else the
// footprint of its box (or of the hypothesis's).
std::optional<SurfaceTop> top_of(const World& world, const std::string& id, const Hypothesis* h) {
  if (h && h->id == id) return surface_top(h->box, Pose{}, {});
  const PerceivedObject* o = world.percepts.find(id);
  if (!o) return std::nullopt;
  return o->type == "surface" ? surface_top(*o) : surface_top(o->box, o->pose, {});
}

// A box of `a`'s size resting on the top `b`, its centre drawn uniformly so that its footprint
// lies within `b`'s grown by `grow` (or its centre anywhere over `b` if it does not fit).
Eigen::AlignedBox3d resting_on(const Eigen::AlignedBox3d& a, const SurfaceTop& b, double grow,
                               std::mt19937_64& rng) {
  const Eigen::Vector3d half = a.sizes() / 2;
  const Eigen::Vector2d across = b.extent(half.head<2>());  // along b's axes
  Eigen::Vector2d at;
  for (int i = 0; i < 2; ++i) {
    double lo = b.lo[i] - grow + across[i], hi = b.hi[i] + grow - across[i];
    if (lo > hi) lo = b.lo[i], hi = b.hi[i];
    at[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  Eigen::Vector3d centre(0, 0, b.height + half.z());
  centre.head<2>() = b.world(at);
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
  std::string explain(const World& w) const override {
    const auto a = box_of(w, a_, nullptr), b = box_of(w, b_, nullptr);
    if (!a || !b) return describe() + ": " + unknown(w, {a_, b_});
    if (box_distance(*a, *b) <= d_) return describe() + " holds";
    return describe() + ": " + a_ + " is " + cm(box_distance(*a, *b)) + " from " + b_;
  }
  // On top of b, anywhere within d of its footprint.
  std::optional<Eigen::AlignedBox3d> propose(const World& w, const std::string& object,
                                             std::mt19937_64& rng) const override {
    if (object != a_) return std::nullopt;
    const auto a = box_of(w, a_, nullptr);
    const auto b = top_of(w, b_, nullptr);
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
  // a's footprint overlaps b's top (a surface's top turned with it), and a's bottom is no lower
  // than b's top by more than the tolerance.
  bool holds(const World& w, const Hypothesis* h) const override {
    const auto a = box_of(w, a_, h);
    const auto b = top_of(w, b_, h);
    if (!a || !b) return false;
    return b->overlaps(a->min().head<2>(), a->max().head<2>()) &&
           a->min().z() >= b->height - kAboveTolerance;
  }
  std::string describe() const override { return "above(" + a_ + ", " + b_ + ")"; }
  std::string explain(const World& w) const override {
    const auto a = box_of(w, a_, nullptr);
    const auto b = top_of(w, b_, nullptr);
    if (!a || !b) return describe() + ": " + unknown(w, {a_, b_});
    if (holds(w, nullptr)) return describe() + " holds";
    if (!b->overlaps(a->min().head<2>(), a->max().head<2>())) {
      return describe() + ": " + a_ + " is not over " + b_;
    }
    return describe() + ": " + a_ + "'s bottom is " + cm(b->height - a->min().z()) + " below " +
           b_ + "'s top";
  }
  // Resting on b's top face, wholly inside it when it fits.
  std::optional<Eigen::AlignedBox3d> propose(const World& w, const std::string& object,
                                             std::mt19937_64& rng) const override {
    if (object != a_) return std::nullopt;
    const auto a = box_of(w, a_, nullptr);
    const auto b = top_of(w, b_, nullptr);
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
  bool holds(const World& w, const Hypothesis*) const override { return !first_off(w); }
  std::string describe() const override {
    std::string s = "postural(" + posture_;
    for (const std::string& c : chains_) s += ", " + c;
    return s + ")";
  }
  std::string explain(const World& w) const override {
    const std::optional<Off> off = first_off(w);
    if (!off) return describe() + " holds";
    std::ostringstream s;
    s << describe() << ": joint " << off->joint << " is " << off->distance
      << " from the posture (tolerance " << tol_ << ")";
    return s.str();
  }

 private:
  struct Off {
    std::string joint;
    double distance;
  };
  // The first joint further than tol_ from the posture; none when the condition holds.
  std::optional<Off> first_off(const World& w) const {
    const Posture& p = w.skills.posture(posture_);
    for (const auto& [chain, values] : p) {
      if (!chains_.empty() && std::find(chains_.begin(), chains_.end(), chain) == chains_.end())
        continue;
      const std::vector<double> q = w.skills.configuration({chain});
      for (size_t i = 0; i < q.size(); ++i) {
        const double distance = std::abs(q[i] - values[i]);
        if (distance > tol_) return Off{w.skills.chain(chain).joints.at(i), distance};
      }
    }
    return std::nullopt;
  }

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
  std::string explain(const World& w) const override {
    return holds(w, nullptr) ? describe() + " holds" : describe() + ": no hand holds " + a_;
  }

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
    const bool tool = known && known->frames.count("grip");
    for (const HandSpec& hand : w.skills.profile().hands) {
      if (side_ != "any" && hand.side != side_) continue;
      const Pose palm = w.skills.frame_pose(hand.palm);
      if ((palm.position - grasp_point).norm() <= kGraspableDistance) return true;
      // A grasp of an object (not a tool's grip) may hold it anywhere within its box: from
      // above, the palm stays over the top of a tall object.
      if (!tool && box->contains(palm.position)) return true;
      // Or within that distance of a part that sticks out (protruding_shapes), held on its
      // own (a mug by its handle).
      if (tool || (h && h->id == a_) || !known) continue;
      for (const size_t i : protruding_shapes(*known)) {
        if (known->shapes[i].bounds().exteriorDistance(palm.position) <= kGraspableDistance) {
          return true;
        }
      }
    }
    return false;
  }
  std::string describe() const override { return "graspable(" + a_ + ", " + side_ + ")"; }
  std::string explain(const World& w) const override {
    const PerceivedObject* known = w.percepts.find(a_);
    if (!known) return describe() + ": " + unknown(w, {a_});
    if (!w.skills.holder_of(a_).empty()) return describe() + ": " + a_ + " is held";
    if (holds(w, nullptr)) return describe() + " holds";
    double nearest = std::numeric_limits<double>::infinity();
    for (const HandSpec& hand : w.skills.profile().hands) {
      if (side_ != "any" && hand.side != side_) continue;
      nearest = std::min(nearest,
                         (w.skills.frame_pose(hand.palm).position - known->grasp_point()).norm());
    }
    if (nearest <= kGraspableDistance) return describe() + " holds";
    return describe() + ": the nearest palm is " + cm(nearest) + " from " + a_ +
           "'s grasp point (at most " + cm(kGraspableDistance) + ")";
  }

 private:
  std::string a_, side_;
};

class InView final : public Condition {
 public:
  explicit InView(std::string a) : a_(std::move(a)) {}
  bool holds(const World& w, const Hypothesis* h) const override {
    const auto box = box_of(w, a_, h);
    return box && in_camera_view(w.skills, *box);
  }
  std::string describe() const override { return "in_view(" + a_ + ")"; }
  std::string explain(const World& w) const override {
    if (!box_of(w, a_, nullptr)) return describe() + ": " + unknown(w, {a_});
    return holds(w, nullptr) ? describe() + " holds"
                             : describe() + ": " + a_ + " is outside the head camera's view";
  }

 private:
  std::string a_;
};

class Exists final : public Condition {
 public:
  explicit Exists(std::string type) : type_(std::move(type)) {}
  bool holds(const World& w, const Hypothesis*) const override {
    return !w.percepts.of_type(type_).empty();
  }
  std::string describe() const override { return "exists(" + type_ + ")"; }
  std::string explain(const World& w) const override {
    return holds(w, nullptr) ? describe() + " holds"
                             : describe() + ": nothing of type " + type_ + " is known";
  }

 private:
  std::string type_;
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
  // all_of: the first clause that fails; any_of: why each fails.
  std::string explain(const World& w) const override {
    if (holds(w, nullptr)) return describe() + " holds";
    if (all_) {
      for (const ConditionPtr& c : c_) {
        if (!c->holds(w, nullptr)) return c->explain(w);
      }
    }
    std::string s = "none of " + std::to_string(c_.size()) + " holds: ";
    for (size_t i = 0; i < c_.size(); ++i) s += (i ? "; " : "") + c_[i]->explain(w);
    return s;
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
  std::string explain(const World& w) const override {
    return holds(w, nullptr) ? describe() + " holds"
                             : describe() + ": " + c_->describe() + " holds";
  }

 private:
  ConditionPtr c_;
};

}  // namespace

std::string Condition::explain(const World& world) const {
  return describe() + (holds(world, nullptr) ? " holds" : " does not hold");
}

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
ConditionPtr in_view(std::string object) { return std::make_shared<InView>(std::move(object)); }
ConditionPtr exists(std::string type) { return std::make_shared<Exists>(std::move(type)); }
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

bool in_camera_view(Skillset& skills, const Eigen::Vector3d& point) {
  const CameraInfo camera = skills.head_camera();
  const Pose pose = skills.frame_pose(camera.frame);
  const Eigen::Vector3d p = pose.orientation.conjugate() * (point - pose.position);
  const double ahead = -p.z();  // the camera looks along -z
  if (ahead <= 0 || p.norm() > camera.range_m) return false;
  const double tan_half_y = std::tan(camera.fovy_rad / 2);
  return std::abs(p.y()) <= ahead * tan_half_y &&
         std::abs(p.x()) <= ahead * tan_half_y * camera.aspect;
}

bool in_camera_view(Skillset& skills, const Eigen::AlignedBox3d& box) {
  for (int i = 0; i < 27; ++i) {
    const Eigen::Vector3d f((i % 3) / 2.0, (i / 3 % 3) / 2.0, (i / 9) / 2.0);
    const Eigen::Vector3d p = box.min() + f.cwiseProduct(box.max() - box.min());
    if (in_camera_view(skills, p)) return true;
  }
  return false;
}

namespace {

bool well_formed_name(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

using Kind = ConditionArgKind;

// The built-in conditions, in the order of the reference (docs/conditions.md); a test checks
// the reference against the registry.
void add_builtins(ConditionRegistry& r) {
  using Args = std::vector<ConditionArg>;
  r.add({"near", 2, 3, {Kind::kObject, Kind::kObject, Kind::kNumber}, [](const Args& a) {
           return near(a[0].name, a[1].name, a.size() == 3 ? a[2].number : 0.10);
         }});
  r.add(
      {"above", 2, 2, {Kind::kObject}, [](const Args& a) { return above(a[0].name, a[1].name); }});
  r.add({"postural", 1, kAnyNumberOfArgs, {Kind::kName}, [](const Args& a) {
           std::vector<std::string> chains;
           for (size_t i = 1; i < a.size(); ++i) chains.push_back(a[i].name);
           return postural(a[0].name, chains);
         }});
  r.add({"grasping", 1, 1, {Kind::kObject}, [](const Args& a) { return grasping(a[0].name); }});
  r.add({"graspable", 1, 2, {Kind::kObject, Kind::kName}, [](const Args& a) {
           return graspable(a[0].name, a.size() == 2 ? a[1].name : "any");
         }});
  r.add({"in_view", 1, 1, {Kind::kObject}, [](const Args& a) { return in_view(a[0].name); }});
  r.add({"exists", 1, 1, {Kind::kName}, [](const Args& a) { return exists(a[0].name); }});
  r.add({"not", 1, 1, {Kind::kCondition}, [](const Args& a) { return negate(a[0].condition); }});
  const auto conditions = [](const Args& a) {
    std::vector<ConditionPtr> inner;
    for (const ConditionArg& arg : a) inner.push_back(arg.condition);
    return inner;
  };
  r.add({"all_of", 1, kAnyNumberOfArgs, {Kind::kCondition}, [conditions](const Args& a) {
           return all_of(conditions(a));
         }});
  r.add({"any_of", 1, kAnyNumberOfArgs, {Kind::kCondition}, [conditions](const Args& a) {
           return any_of(conditions(a));
         }});
}

// Recursive descent over: call := name '(' [arg {',' arg}] ')'; arg := call | word.
class ConditionParser {
 public:
  // `objects`, if given, collects the words passed as kObject arguments.
  ConditionParser(const std::string& text, const ConditionRegistry& registry,
                  std::vector<std::string>* objects = nullptr)
      : text_(text), registry_(registry), objects_(objects) {}

  ConditionPtr parse() {
    ConditionPtr c = call();
    skip_space();
    if (pos_ != text_.size()) {
      error("unexpected '" + shortened(text_.substr(pos_)) + "' after the condition");
    }
    return c;
  }

 private:
  struct Arg {
    std::string word;    // a name or number
    ConditionPtr inner;  // a nested condition
  };

  [[noreturn]] void error(const std::string& what) const {
    throw std::invalid_argument("condition '" + shortened(text_) + "': " + what);
  }
  static std::string shortened(const std::string& text) {
    return text.size() <= 120 ? text : text.substr(0, 100) + "...";
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  std::string word() {
    skip_space();
    const size_t start = pos_;
    while (pos_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_' ||
            text_[pos_] == '.' || text_[pos_] == '-' || text_[pos_] == '$')) {
      ++pos_;
    }
    if (pos_ == start) {
      error(pos_ < text_.size() ? "expected a name at '" + shortened(text_.substr(pos_)) + "'"
                                : "expected a name at the end");
    }
    return text_.substr(start, pos_ - start);
  }
  bool peek(char c) {
    skip_space();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  void expect(char c) {
    if (!peek(c)) error(std::string("expected '") + c + "' at position " + std::to_string(pos_));
    ++pos_;
  }
  ConditionPtr call() {
    const std::string name = word();
    expect('(');
    // Conditions nest through not, all_of and any_of; parsing, evaluating and describing them
    // recurse, so the depth is bounded.
    if (++depth_ > kMaxConditionDepth) {
      error("nested more than " + std::to_string(kMaxConditionDepth) + " levels deep");
    }
    std::vector<Arg> args;
    if (!peek(')')) {
      do {
        args.push_back(arg());
      } while (peek(',') && (++pos_, true));
    }
    expect(')');
    --depth_;
    return make(name, args);
  }
  Arg arg() {
    const size_t start = pos_;
    const std::string w = word();
    if (peek('(')) {
      pos_ = start;
      return Arg{"", call()};
    }
    return Arg{w, nullptr};
  }
  std::string name_arg(const std::string& f, const std::vector<Arg>& args, size_t i) {
    if (args[i].inner) error(f + ": argument " + std::to_string(i + 1) + " must be a name");
    return args[i].word;
  }
  double number_arg(const std::string& f, const std::vector<Arg>& args, size_t i) {
    const std::string w = name_arg(f, args, i);
    try {
      size_t used = 0;
      const double v = std::stod(w, &used);
      if (used == w.size() && std::isfinite(v) && v >= 0) return v;
    } catch (const std::exception&) {
    }
    error(f + ": argument " + std::to_string(i + 1) + " must be a non-negative number, not '" + w +
          "'");
  }
  ConditionPtr condition_arg(const std::string& f, const std::vector<Arg>& args, size_t i) {
    if (!args[i].inner) error(f + ": argument " + std::to_string(i + 1) + " must be a condition");
    return args[i].inner;
  }
  void arity(const std::string& f, const std::vector<Arg>& args, size_t lo, size_t hi) {
    if (args.size() < lo || args.size() > hi) {
      error(f + " takes " + std::to_string(lo) +
            (hi == lo                 ? ""
             : hi == kAnyNumberOfArgs ? " or more"
                                      : " to " + std::to_string(hi)) +
            " argument" + (lo == 1 && hi == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
    }
  }
  ConditionPtr make(const std::string& f, const std::vector<Arg>& args) {
    const ConditionType* type = registry_.find(f);
    if (type == nullptr) {
      std::string known;
      for (const std::string& name : registry_.names()) {
        known += (known.empty() ? "" : ", ") + name;
      }
      error("unknown condition '" + f + "' (known: " + known + ")");
    }
    arity(f, args, type->min_args, type->max_args);
    std::vector<ConditionArg> checked(args.size());
    for (size_t i = 0; i < args.size(); ++i) {
      switch (type->kinds[std::min(i, type->kinds.size() - 1)]) {
        case Kind::kName:
          checked[i].name = name_arg(f, args, i);
          break;
        case Kind::kObject:
          checked[i].name = name_arg(f, args, i);
          if (objects_) objects_->push_back(checked[i].name);
          break;
        case Kind::kNumber:
          checked[i].number = number_arg(f, args, i);
          break;
        case Kind::kCondition:
          checked[i].condition = condition_arg(f, args, i);
          break;
      }
    }
    ConditionPtr made = type->make(checked);
    if (!made) throw std::logic_error("condition '" + f + "' made no condition");
    return made;
  }

  const std::string& text_;
  const ConditionRegistry& registry_;
  std::vector<std::string>* objects_;
  size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

void ConditionRegistry::add(ConditionType type) {
  const std::string what = "condition '" + type.name + "'";
  if (!well_formed_name(type.name)) {
    throw std::invalid_argument("condition name '" + type.name +
                                "' is not 1 to 64 of A-Z a-z 0-9 _");
  }
  if (find(type.name) != nullptr) throw std::invalid_argument(what + " is registered twice");
  if (type.min_args > type.max_args) {
    throw std::invalid_argument(what + ": min_args " + std::to_string(type.min_args) +
                                " is above max_args " + std::to_string(type.max_args));
  }
  if (type.max_args > 0 && type.kinds.empty()) {
    throw std::invalid_argument(what + " takes arguments but declares no argument kinds");
  }
  if (!type.make) throw std::invalid_argument(what + " has no make function");
  types_.push_back(std::move(type));
}

const ConditionType* ConditionRegistry::find(const std::string& name) const {
  for (const ConditionType& type : types_) {
    if (type.name == name) return &type;
  }
  return nullptr;
}

std::vector<std::string> ConditionRegistry::names() const {
  std::vector<std::string> out;
  for (const ConditionType& type : types_) out.push_back(type.name);
  return out;
}

ConditionRegistry& condition_registry() {
  static ConditionRegistry registry = [] {
    ConditionRegistry r;
    add_builtins(r);
    return r;
  }();
  return registry;
}

ConditionRegistration::ConditionRegistration(ConditionType type) {
  condition_registry().add(std::move(type));
}

ConditionPtr parse_condition(const std::string& text, const ConditionRegistry& registry) {
  return ConditionParser(text, registry).parse();
}

std::vector<std::string> condition_object_names(const std::string& text,
                                                const ConditionRegistry& registry) {
  std::vector<std::string> out;
  ConditionParser(text, registry, &out).parse();
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
