// PhysicsContacts on small models made for the cases the built-in scenes do not have: where
// its contacts equal mj_collision's, where it hands over to mj_collision, and MuJoCo 2.2.2's
// doubled floor contacts, which it does not repeat.
#include "taskmatrix/mujoco/physics_contacts.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "taskmatrix/mujoco/mujoco_handles.h"

namespace taskmatrix::mujoco {
namespace {

// A floor plane on a static body of its own (as the composition places a room's geoms), a table
// top (a box) on another, a ball resting on the table, a ball on the floor at the plane's
// centre and a capsule on a hinge beside the table. `option` is the model's <option> element,
// `margin` every geom's.
ModelPtr small_world(const std::string& option = "<option/>", const std::string& margin = "0") {
  const std::string m = " margin=\"" + margin + "\"";
  return compile_mjcf_text(
      "<mujoco>" + option +
          "<worldbody>"
          "<body name=\"floor\"><geom type=\"plane\" size=\"3 3 0.1\"" +
          m +
          "/></body>"
          "<body name=\"table\" pos=\"1 0 0.5\"><geom type=\"box\" size=\"0.6 0.4 0.02\"" +
          m +
          "/></body>"
          "<body name=\"ball\" pos=\"1.2 0 0.569\"><freejoint/><geom type=\"sphere\" "
          "size=\"0.05\"" +
          m +
          "/></body>"
          "<body name=\"low_ball\" pos=\"0 0 0.049\"><freejoint/><geom type=\"sphere\" "
          "size=\"0.05\"" +
          m +
          "/></body>"
          "<body name=\"arm\" pos=\"1.0 0.5 0.6\"><joint type=\"hinge\" axis=\"1 0 0\"/>"
          "<geom type=\"capsule\" fromto=\"0 0 0 0 -0.1 -0.05\" size=\"0.03\"" +
          m +
          "/></body>"
          "</worldbody></mujoco>",
      "small_world");
}

struct Both {
  DataPtr mine, theirs;
};

Both collide_both(const mjModel* m, const PhysicsContacts& contacts) {
  Both b{make_data(m), make_data(m)};
  mj_kinematics(m, b.mine.get());
  mj_kinematics(m, b.theirs.get());
  contacts.collide(m, b.mine.get());
  mj_collision(m, b.theirs.get());
  return b;
}

int count_pair(const mjData* d, int g1, int g2) {
  int n = 0;
  for (int i = 0; i < d->ncon; ++i) {
    n += (d->contact[i].geom1 == g1 && d->contact[i].geom2 == g2) ||
         (d->contact[i].geom1 == g2 && d->contact[i].geom2 == g1);
  }
  return n;
}

TEST(PhysicsContacts, FindsTheBallOnTheTableOnceAndTheFloorBallOnceWhereMuJoCoListsItTwice) {
  const ModelPtr model = small_world();
  const mjModel* m = model.get();
  const PhysicsContacts contacts(m);
  ASSERT_TRUE(contacts.usable());
  const Both b = collide_both(m, contacts);
  const int plane = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "floor")];
  const int top = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "table")];
  const int ball = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "ball")];
  const int low = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "low_ball")];
  EXPECT_EQ(count_pair(b.mine.get(), top, ball), 1);
  EXPECT_EQ(count_pair(b.theirs.get(), top, ball), 1);
  // MuJoCo 2.2.2 pairs the floor's body with every body, then again with what its sweep finds
  // overlapping the plane's centre (fixed in MuJoCo 2.3.2).
  EXPECT_EQ(count_pair(b.mine.get(), plane, low), 1);
  EXPECT_EQ(count_pair(b.theirs.get(), plane, low), 2)
      << "MuJoCo no longer doubles the floor contact: physics_contacts.h says it does";
  EXPECT_EQ(b.mine->ncon, b.theirs->ncon - 1);
}

TEST(PhysicsContacts, HandsOverToMuJoCoWhereItWouldFindOtherContacts) {
  // A negative margin shrinks MuJoCo's broadphase boxes; the override's margin is not theirs.
  for (const auto& [option, margin] :
       {std::pair<std::string, std::string>{"<option/>", "-0.001"},
        {"<option o_margin=\"0.05\"><flag override=\"enable\"/></option>", "0"}}) {
    const ModelPtr model = small_world(option, margin);
    const mjModel* m = model.get();
    const PhysicsContacts contacts(m);
    const Both b = collide_both(m, contacts);
    ASSERT_EQ(b.mine->ncon, b.theirs->ncon) << option << " margin " << margin;
    for (int i = 0; i < b.mine->ncon; ++i) {
      EXPECT_EQ(b.mine->contact[i].geom1, b.theirs->contact[i].geom1);
      EXPECT_EQ(b.mine->contact[i].geom2, b.theirs->contact[i].geom2);
      EXPECT_EQ(b.mine->contact[i].dist, b.theirs->contact[i].dist);
    }
    // MuJoCo's own pass ran: the floor contact doubled as MuJoCo doubles it.
    const int plane = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "floor")];
    const int low = m->body_geomadr[mj_name2id(m, mjOBJ_BODY, "low_ball")];
    EXPECT_EQ(count_pair(b.mine.get(), plane, low), 2) << option << " margin " << margin;
  }
}

TEST(PhysicsContacts, AFullContactArrayKeepsWhatMuJoCoKeeps) {
  // Room for one contact: which one is kept depends on the order pairs are tried in.
  const ModelPtr model = small_world();
  mjModel* m = model.get();
  m->nconmax = 1;
  const PhysicsContacts contacts(m);
  DataPtr mine = make_data(m), theirs = make_data(m);
  mj_kinematics(m, mine.get());
  mj_kinematics(m, theirs.get());
  contacts.collide(m, mine.get());
  mj_collision(m, theirs.get());
  ASSERT_EQ(mine->ncon, 1);
  ASSERT_EQ(theirs->ncon, 1);
  EXPECT_EQ(mine->contact[0].geom1, theirs->contact[0].geom1);
  EXPECT_EQ(mine->contact[0].geom2, theirs->contact[0].geom2);
  EXPECT_EQ(mine->warning[mjWARN_CONTACTFULL].number, theirs->warning[mjWARN_CONTACTFULL].number);
}

}  // namespace
}  // namespace taskmatrix::mujoco
