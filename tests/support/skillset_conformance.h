// The skillset conformance suite: what every backend of core::Skillset must do the same way
// (argument checks, attachment bookkeeping, commands read back, plan statuses, work counts).
// A backend joins by instantiating the suite with a factory:
//   INSTANTIATE_TEST_SUITE_P(Mine, SkillsetConformance,
//                            ::testing::Values(test::Backend{"mine", make_mine, "cup"}));
// The skillset must be at its start: the "left_arm" chain free to move a little, `object` a
// graspable object of its world.
#pragma once

#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "taskmatrix/core/skillset.h"

namespace taskmatrix::test {

struct Backend {
  std::string name;
  std::function<std::unique_ptr<core::Skillset>()> make;
  std::string object;  // a graspable object
};
inline void PrintTo(const Backend& b, std::ostream* os) { *os << b.name; }
inline std::string backend_name(const ::testing::TestParamInfo<Backend>& info) {
  return info.param.name;
}

class SkillsetConformance : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { skills_ = GetParam().make(); }
  core::Skillset& skills() { return *skills_; }

 private:
  std::unique_ptr<core::Skillset> skills_;
};

}  // namespace taskmatrix::test
