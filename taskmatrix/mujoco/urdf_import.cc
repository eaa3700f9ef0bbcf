#include "taskmatrix/mujoco/urdf_import.h"

#include <console_bridge/console.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/text_file.h"
#include "taskmatrix/mujoco/mujoco_handles.h"

namespace taskmatrix::mujoco {

using core::InputError;

namespace {

std::string format_numbers(std::initializer_list<double> values) {
  std::string out;
  char buf[64];
  for (double v : values) {
    std::snprintf(buf, sizeof buf, "%s%.9g", out.empty() ? "" : " ", v);
    out += buf;
  }
  return out;
}

void validate_urdf(const core::RobotProfile& profile, const std::string& text) {
  const std::string file = profile.model_file.string();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(text);
  if (!urdf) {
    throw InputError(file, "robot",
                     "urdfdom rejects the file (malformed XML, a missing link, a joint cycle or "
                     "more than one root)");
  }
  if (!urdf->getRoot()) throw InputError(file, "robot", "has no root link");
  for (const core::ChainSpec& chain : profile.chains) {
    for (const std::string& name : chain.joints) {
      const std::string key = "joint[" + name + "]";
      urdf::JointConstSharedPtr joint = urdf->getJoint(name);
      if (!joint) {
        throw InputError(file, key,
                         "missing (profile " + profile.profile_file.string() +
                             " names it in chain '" + chain.name + "')");
      }
      if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::PRISMATIC) {
        throw InputError(file, key,
                         "must be revolute or prismatic with limits (continuous, fixed, planar and "
                         "floating joints cannot be planned over)");
      }
      if (!joint->limits || !(joint->limits->lower < joint->limits->upper)) {
        throw InputError(file, key, "needs <limit lower upper> with lower < upper");
      }
    }
  }
  for (const core::HandSpec& hand : profile.hands) {
    for (const core::FingerSpec& finger : hand.fingers) {
      for (const std::string& body : finger.bodies) {
        if (!urdf->getLink(body)) {
          throw InputError(
              file, "link[" + body + "]",
              "missing (profile names it as a finger segment of the " + hand.side + " hand)");
        }
      }
    }
  }
}

// mj_saveLastXML writes the model MuJoCo last parsed to a file: serialize with a lock.
std::string compile_and_save(const core::RobotProfile& profile) {
  std::lock_guard<std::recursive_mutex> lock(mujoco_loader_mutex());
  ModelPtr model = compile_file(profile.model_file.string());
  char tmpl[] = "/tmp/taskmatrix_urdf_XXXXXX";
  const int fd = mkstemp(tmpl);
  if (fd < 0) throw InputError(profile.model_file.string(), "", "cannot create a temporary file");
  close(fd);
  struct Remove {
    const char* path;
    ~Remove() { std::filesystem::remove(path); }
  } remove_later{tmpl};
  char error[512] = "";
  const int ok = mj_saveLastXML(tmpl, model.get(), error, sizeof error);
  std::string text = ok ? io::read_text_file(tmpl) : std::string();
  if (!ok) {
    throw InputError(profile.model_file.string(), "",
                     std::string("MuJoCo cannot save it: ") + error);
  }
  return text;
}

tinyxml2::XMLElement* find_body(tinyxml2::XMLElement* e, const std::string& name) {
  for (tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::string_view(c->Name()) == "body" && c->Attribute("name") &&
        name == c->Attribute("name")) {
      return c;
    }
    if (tinyxml2::XMLElement* found = find_body(c, name)) return found;
  }
  return nullptr;
}

void collect_joints(tinyxml2::XMLElement* e, std::vector<tinyxml2::XMLElement*>& out) {
  for (tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::string_view(c->Name()) == "joint") out.push_back(c);
    collect_joints(c, out);
  }
}

}  // namespace

std::string import_urdf_as_mjcf(const core::RobotProfile& profile) {
  const std::string file = profile.model_file.string();
  validate_urdf(profile, io::read_text_file(profile.model_file));
  const std::string mjcf = compile_and_save(profile);

  tinyxml2::XMLDocument doc;
  if (doc.Parse(mjcf.c_str(), mjcf.size()) != tinyxml2::XML_SUCCESS || !doc.RootElement()) {
    throw InputError(file, "", "MuJoCo's converted model is not readable XML");
  }
  tinyxml2::XMLElement* root = doc.RootElement();
  tinyxml2::XMLElement* world = root->FirstChildElement("worldbody");
  if (!world) throw InputError(file, "", "the converted model has no bodies");

  const core::CameraSpec& cam = profile.head_camera;
  tinyxml2::XMLElement* cam_body = find_body(world, cam.body);
  if (!cam_body) {
    throw InputError(profile.profile_file.string(), "head_camera.body",
                     "link '" + cam.body + "' is not in " + file);
  }
  tinyxml2::XMLElement* camera = doc.NewElement("camera");
  camera->SetAttribute("name", cam.name.c_str());
  camera->SetAttribute("pos", format_numbers({cam.pos[0], cam.pos[1], cam.pos[2]}).c_str());
  camera->SetAttribute("xyaxes", format_numbers({cam.xyaxes[0], cam.xyaxes[1], cam.xyaxes[2],
                                                 cam.xyaxes[3], cam.xyaxes[4], cam.xyaxes[5]})
                                     .c_str());
  camera->SetAttribute("fovy", cam.fovy_deg);
  cam_body->InsertFirstChild(camera);

  // A position actuator on every joint, gains by chain.
  std::map<std::string, double> kp_of_joint;
  for (const core::ChainSpec& chain : profile.chains) {
    const bool hand = chain.name.ends_with("_hand");
    double kp = hand ? kDefaultHandKp : kDefaultArmKp;
    if (auto it = profile.actuator_kp.find(chain.name); it != profile.actuator_kp.end())
      kp = it->second;
    for (const std::string& j : chain.joints) kp_of_joint[j] = kp;
  }
  std::vector<tinyxml2::XMLElement*> joints;
  collect_joints(world, joints);
  tinyxml2::XMLElement* actuators = root->FirstChildElement("actuator");
  if (!actuators) actuators = root->InsertEndChild(doc.NewElement("actuator"))->ToElement();
  for (tinyxml2::XMLElement* j : joints) {
    const char* name = j->Attribute("name");
    const char* range = j->Attribute("range");
    if (!name || !range) {
      throw InputError(file, std::string("joint[") + (name ? name : "?") + "]",
                       "needs a name and limits (<limit lower upper>) to get a position actuator");
    }
    const auto it = kp_of_joint.find(name);
    tinyxml2::XMLElement* act = doc.NewElement("position");
    act->SetAttribute("name", (std::string("act_") + name).c_str());
    act->SetAttribute("joint", name);
    act->SetAttribute("kp", it != kp_of_joint.end() ? it->second : kDefaultArmKp);
    act->SetAttribute("ctrllimited", "true");
    act->SetAttribute("ctrlrange", range);
    actuators->InsertEndChild(act);
  }
  // MuJoCo writes a <size> and <compiler> of its own; drop what would conflict when composed.
  // meshdir and texturedir stay: composition resolves the mesh files against them and the
  // URDF's folder.
  if (tinyxml2::XMLElement* compiler = root->FirstChildElement("compiler")) {
    for (const char* attr : {"fusestatic", "discardvisual", "balanceinertia"}) {
      compiler->DeleteAttribute(attr);
    }
  }
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

}  // namespace taskmatrix::mujoco
