#include <stdexcept>

#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::core {

void PlannerRegistry::add(PlannerType type) {
  const bool well_formed = !type.name.empty() && type.name.size() <= 64 &&
                           std::all_of(type.name.begin(), type.name.end(), [](char c) {
                             return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                                    (c >= '0' && c <= '9') || c == '_' || c == '-';
                           });
  if (!well_formed) {
    throw std::invalid_argument("planner name '" + type.name +
                                "' is not 1 to 64 of A-Z a-z 0-9 _ -");
  }
  if (!type.make) throw std::invalid_argument("planner " + type.name + " has no make function");
  if (types_.count(type.name)) {
    throw std::invalid_argument("planner '" + type.name + "' is already registered");
  }
  std::string name = type.name;
  types_.emplace(std::move(name), std::move(type));
}

const PlannerType* PlannerRegistry::find(const std::string& name) const {
  const auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> PlannerRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

std::string PlannerRegistry::check(const std::string& name, const RawParams& raw) const {
  const PlannerType* type = find(name);
  if (type == nullptr) {
    std::string known;
    for (const auto& [n, t] : types_) known += (known.empty() ? "" : ", ") + n;
    return "unknown planner '" + name + "' (known: " + known + ")";
  }
  try {
    const Params params = check_params(type->params, raw);
    if (type->check) {
      if (std::string bad = type->check(params.values()); !bad.empty()) {
        return "planner " + name + ": " + bad;
      }
    }
  } catch (const std::invalid_argument& e) {
    return "planner " + name + ": " + e.what();
  }
  return "";
}

std::unique_ptr<Planner> PlannerRegistry::make(const std::string& name,
                                               const RawParams& raw) const {
  if (std::string bad = check(name, raw); !bad.empty()) throw std::invalid_argument(bad);
  const PlannerType& type = *find(name);
  std::unique_ptr<Planner> planner = type.make(check_params(type.params, raw).values());
  if (!planner) throw std::invalid_argument("planner " + name + " made no planner");
  return planner;
}

PlannerRegistry& planner_registry() {
  static PlannerRegistry registry;
  return registry;
}

}  // namespace taskmatrix::core
