#include "taskmatrix/mujoco/mjcf_compose.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <tinyxml2.h>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/perceptual_model.h"

namespace taskmatrix::mujoco {

using core::InputError;
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

namespace {

constexpr std::array<std::string_view, 4> kMergedSingletons = {"option", "size", "visual",
                                                               "statistic"};
constexpr std::array<std::string_view, 8> kAppendedSections = {
    "asset", "worldbody", "actuator", "sensor", "contact", "equality", "tendon", "custom"};

bool is_one_of(std::string_view name, auto const& list) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

void parse(XMLDocument& doc, const MjcfSource& src) {
  if (doc.Parse(src.text.c_str(), src.text.size()) != tinyxml2::XML_SUCCESS) {
    throw InputError(src.file, "", std::string("not well-formed XML: ") + doc.ErrorName(),
                     doc.ErrorLineNum());
  }
  const XMLElement* root = doc.RootElement();
  if (!root || std::strcmp(root->Name(), "mujoco") != 0) {
    throw InputError(src.file, root ? root->Name() : "", "the root element must be <mujoco>",
                     root ? root->GetLineNum() : 0);
  }
}

// Copies src's attributes into dst where dst lacks them; recurses into child elements that
// appear once in both (visual/global, option/flag).
void merge_attributes(XMLElement* dst, const XMLElement* src) {
  for (const tinyxml2::XMLAttribute* a = src->FirstAttribute(); a; a = a->Next()) {
    if (!dst->Attribute(a->Name())) dst->SetAttribute(a->Name(), a->Value());
  }
  for (const XMLElement* c = src->FirstChildElement(); c; c = c->NextSiblingElement()) {
    XMLElement* same = dst->FirstChildElement(c->Name());
    if (same) {
      merge_attributes(same, c);
    } else {
      dst->InsertEndChild(c->DeepClone(dst->GetDocument()));
    }
  }
}

class Composer {
 public:
  Composer() {
    root_ = out_.NewElement("mujoco");
    out_.InsertFirstChild(root_);
  }

  void add(const MjcfSource& src, const XMLElement* root) {
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string_view name = e->Name();
      if (name == "compiler") {
        merge_compiler(src, e);
      } else if (is_one_of(name, kMergedSingletons)) {
        merge_attributes(section(name), e);
      } else if (is_one_of(name, kAppendedSections)) {
        XMLElement* dst = section(name);
        for (const XMLNode* c = e->FirstChild(); c; c = c->NextSibling()) {
          if (c->ToElement()) dst->InsertEndChild(c->DeepClone(&out_));
        }
      } else if (name == "default") {
        merge_default(src, e);
      } else if (name == "keyframe") {
        // A model's stored poses (a public model's "home"): their qpos sizes do not survive
        // composition, and a trial starts from the profile's rest posture anyway.
        continue;
      } else {
        throw InputError(src.file, std::string(name),
                         "element <" + std::string(name) +
                             "> cannot be composed into a scene (see models/README.md)",
                         e->GetLineNum());
      }
    }
  }

  XMLElement* section(std::string_view name) {
    XMLElement* e = root_->FirstChildElement(std::string(name).c_str());
    if (!e) e = root_->InsertEndChild(out_.NewElement(std::string(name).c_str()))->ToElement();
    return e;
  }

  XMLDocument& doc() { return out_; }
  XMLElement* root() { return root_; }

 private:
  void merge_compiler(const MjcfSource& src, const XMLElement* e) {
    XMLElement* dst = section("compiler");
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      const char* existing = dst->Attribute(a->Name());
      if (existing && std::strcmp(existing, a->Value()) != 0) {
        throw InputError(src.file, std::string("compiler.") + a->Name(),
                         "is '" + std::string(a->Value()) + "' but the other file says '" +
                             existing + "'; robot and environment must agree",
                         e->GetLineNum());
      }
      dst->SetAttribute(a->Name(), a->Value());
    }
  }

  void merge_default(const MjcfSource& src, const XMLElement* e) {
    XMLElement* dst = section("default");
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::strcmp(c->Name(), "default") != 0 && dst->FirstChildElement(c->Name())) {
        throw InputError(src.file, std::string("default.") + c->Name(),
                         "both robot and environment set the top-level default <" +
                             std::string(c->Name()) + ">; put one of them in a named class",
                         c->GetLineNum());
      }
      dst->InsertEndChild(c->DeepClone(&out_));
    }
  }

  XMLDocument out_;
  XMLElement* root_;
};

// <include file="..."/> replaced by the children of the named file's <mujoco> root, as MuJoCo
// does (a path relative to the including model's folder; included files may include others,
// up to a depth that catches a file including itself).
void inline_includes(XMLElement* parent, const MjcfSource& src, int depth = 0) {
  namespace fs = std::filesystem;
  for (XMLElement* e = parent->FirstChildElement(); e;) {
    XMLElement* next = e->NextSiblingElement();
    if (std::strcmp(e->Name(), "include") != 0) {
      inline_includes(e, src, depth);
      e = next;
      continue;
    }
    const char* file = e->Attribute("file");
    if (!file || !*file) {
      throw InputError(src.file, "include.file", "an <include> must name a file", e->GetLineNum());
    }
    const fs::path path = fs::path(file).is_absolute()
                              ? fs::path(file)
                              : fs::absolute(fs::path(src.file)).parent_path() / file;
    if (depth >= 8) {
      throw InputError(
          src.file, "include.file",
          "includes nest more than 8 deep (does '" + std::string(file) + "' include itself?)",
          e->GetLineNum());
    }
    std::ifstream in(path);
    if (!in) {
      throw InputError(src.file, "include.file", "cannot read '" + path.string() + "'",
                       e->GetLineNum());
    }
    const MjcfSource included{std::string(std::istreambuf_iterator<char>(in), {}), path.string()};
    XMLDocument doc;
    parse(doc, included);
    inline_includes(doc.RootElement(), included, depth + 1);
    XMLNode* after = e;  // the copies go where the <include> was, in order
    for (const XMLElement* c = doc.RootElement()->FirstChildElement(); c;
         c = c->NextSiblingElement()) {
      after = parent->InsertAfterChild(after, c->DeepClone(parent->GetDocument()));
    }
    parent->DeleteChild(e);
    e = next;
  }
}

// Asset files (meshes, height fields, skins, textures) are named relative to their model
// file's folder and the compiler's meshdir, texturedir or assetdir; the composed scene
// compiles from memory, with no folder of its own. Each relative name becomes the absolute
// path MuJoCo would have opened for the file alone, and the source's directory attributes
// go (two files' meshdirs would otherwise conflict, or one would apply to the other's files).
void resolve_asset_files(XMLElement* root, const MjcfSource& src) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::absolute(fs::path(src.file)).parent_path();
  XMLElement* compiler = root->FirstChildElement("compiler");
  auto dir_attribute = [&](const char* name) -> std::string {
    const char* value = compiler ? compiler->Attribute(name) : nullptr;
    if (value) return value;
    const char* asset_dir = compiler ? compiler->Attribute("assetdir") : nullptr;
    return asset_dir ? asset_dir : "";
  };
  const fs::path mesh_dir = folder / dir_attribute("meshdir");
  const fs::path texture_dir = folder / dir_attribute("texturedir");
  for (XMLElement* assets = root->FirstChildElement("asset"); assets;
       assets = assets->NextSiblingElement("asset")) {
    for (XMLElement* a = assets->FirstChildElement(); a; a = a->NextSiblingElement()) {
      const std::string_view kind = a->Name();
      const bool texture = kind == "texture";
      if (!texture && kind != "mesh" && kind != "hfield" && kind != "skin") continue;
      for (const char* attribute :
           {"file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"}) {
        const char* name = a->Attribute(attribute);
        if (!name || !*name || fs::path(name).is_absolute()) continue;
        const fs::path full = ((texture ? texture_dir : mesh_dir) / name).lexically_normal();
        a->SetAttribute(attribute, full.string().c_str());
      }
    }
  }
  if (compiler) {
    for (const char* name : {"meshdir", "texturedir", "assetdir"}) compiler->DeleteAttribute(name);
  }
}

// MJCF's default angle unit is degrees, so a file without <compiler angle> means degree.
std::string effective_angle(const XMLElement* root) {
  const XMLElement* compiler = root->FirstChildElement("compiler");
  const char* angle = compiler ? compiler->Attribute("angle") : nullptr;
  return angle ? angle : "degree";
}

// The numbers of an attribute, scaled by `factor` from index `first` on, written back.
void scale_numbers(XMLElement* e, const char* attribute, const char* value, double factor,
                   size_t first, const MjcfSource& src) {
  std::vector<double> numbers;
  const char* p = value;
  while (true) {
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    if (!*p) break;
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v)) {
      throw InputError(src.file, std::string(e->Name()) + "." + attribute,
                       "'" + std::string(value) + "' is not a list of numbers", e->GetLineNum());
    }
    numbers.push_back(v);
    p = end;
  }
  std::string out;
  for (size_t i = 0; i < numbers.size(); ++i) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", i >= first ? numbers[i] * factor : numbers[i]);
    out += (i ? " " : "") + std::string(buf);
  }
  e->SetAttribute(attribute, out.c_str());
}

// A file in degrees (MJCF's default) rewritten in radians, as MuJoCo's compiler converts it:
// orientations (`euler`, the angle of `axisangle`) on every element, and a hinge or ball
// joint's `range` (a hinge's `ref` and `springref` too), wherever the joint takes them from:
// its own attributes or its class's defaults (`class`, the bodies' `childclass`, the nesting
// of <default>), written onto the joint itself so that a slide joint sharing those defaults
// keeps its metres. What MuJoCo leaves as written stays so (an actuator's `ctrlrange`, a
// joint's `margin`, a camera's `fovy`, which is always degrees).
void degrees_to_radians(XMLElement* root, const MjcfSource& src) {
  constexpr double kToRadians = M_PI / 180.0;
  // class -> (parent class, its <joint> defaults)
  std::map<std::string, std::pair<std::string, const XMLElement*>> classes;
  std::function<void(const XMLElement*, const std::string&)> collect_defaults =
      [&](const XMLElement* d, const std::string& parent) {
        const char* name = d->Attribute("class");
        const std::string cls = name ? name : "main";
        classes[cls] = {parent, d->FirstChildElement("joint")};
        for (const XMLElement* c = d->FirstChildElement("default"); c;
             c = c->NextSiblingElement("default")) {
          collect_defaults(c, cls);
        }
      };
  for (const XMLElement* d = root->FirstChildElement("default"); d;
       d = d->NextSiblingElement("default")) {
    collect_defaults(d, "");
  }
  auto joint_attribute = [&](const XMLElement* joint, const std::string& cls,
                             const char* name) -> const char* {
    if (const char* own = joint->Attribute(name)) return own;
    for (std::string c = cls; !c.empty();) {
      const auto it = classes.find(c);
      if (it == classes.end()) break;
      if (it->second.second) {
        if (const char* v = it->second.second->Attribute(name)) return v;
      }
      c = it->second.first;
    }
    return nullptr;
  };
  std::function<void(XMLElement*, const std::string&)> convert = [&](XMLElement* e,
                                                                     const std::string& cls) {
    if (const char* euler = e->Attribute("euler"))
      scale_numbers(e, "euler", euler, kToRadians, 0, src);
    if (const char* aa = e->Attribute("axisangle"))
      scale_numbers(e, "axisangle", aa, kToRadians, 3, src);
    const std::string_view name = e->Name();
    std::string child_class = cls;
    if (name == "body") {
      if (const char* c = e->Attribute("childclass")) child_class = c;
    }
    // A body's joint; a <joint> in <equality> or a fixed <tendon> names a joint, it is not one.
    const bool outside_bodies = cls.front() == '<';
    if (name == "joint" && !outside_bodies) {
      const char* own_class = e->Attribute("class");
      const std::string joint_class = own_class ? own_class : cls;
      const char* type = joint_attribute(e, joint_class, "type");
      const std::string kind = type ? type : "hinge";
      for (const char* attribute : {"range", "ref", "springref"}) {
        const bool angular =
            kind == "hinge" || (kind == "ball" && std::strcmp(attribute, "range") == 0);
        if (!angular) continue;
        if (const char* value = joint_attribute(e, joint_class, attribute)) {
          const std::string copy = value;  // the default's text, not to be rewritten in place
          scale_numbers(e, attribute, copy.c_str(), kToRadians, 0, src);
        }
      }
    }
    for (XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      convert(c, outside_bodies ? cls : child_class);
    }
  };
  // Joints take their values in <worldbody>; elsewhere (<default> included: a joint takes its
  // class's values above) only orientations are converted.
  for (XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    convert(e, std::strcmp(e->Name(), "worldbody") == 0 ? "main" : "<outside bodies>");
  }
  XMLElement* compiler = root->FirstChildElement("compiler");
  if (!compiler) {
    compiler = root->GetDocument()->NewElement("compiler");
    root->InsertFirstChild(compiler);
  }
  compiler->SetAttribute("angle", "radian");
}

}  // namespace

std::string obstacle_body_name(int slot) { return "tm_obstacle_" + std::to_string(slot); }

std::string obstacle_name(int slot) { return core::obstacle_id(slot); }

int obstacle_slot_named(const std::string& name) {
  if (name.rfind(core::kObstacleIdPrefix, 0) != 0) return -1;
  const std::string digits = name.substr(core::kObstacleIdPrefix.size());
  if (digits.empty() || digits.size() > 6 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return -1;
  }
  return std::stoi(digits);
}

std::string obstacle_geom_name(int slot, core::ObstacleShape shape) {
  return obstacle_body_name(slot) + "_" + core::to_string(shape);
}

std::string compose_scene_mjcf(const MjcfSource& robot, const MjcfSource& environment,
                               const CompositionOptions& options) {
  XMLDocument robot_doc, env_doc;
  parse(robot_doc, robot);
  parse(env_doc, environment);
  inline_includes(robot_doc.RootElement(), robot);
  inline_includes(env_doc.RootElement(), environment);
  resolve_asset_files(robot_doc.RootElement(), robot);
  resolve_asset_files(env_doc.RootElement(), environment);

  // Both files in radians: one in degrees (MJCF's default: a public model without
  // <compiler angle>) is converted, so that the two compose; any other unit is refused.
  for (auto [doc, src] : {std::pair{&robot_doc, &robot}, std::pair{&env_doc, &environment}}) {
    const std::string angle = effective_angle(doc->RootElement());
    if (angle == "degree") {
      degrees_to_radians(doc->RootElement(), *src);
    } else if (angle != "radian") {
      throw InputError(src->file, "compiler.angle",
                       "is '" + angle + "'; MJCF's angle units are 'degree' or 'radian'");
    }
  }

  Composer composer;
  composer.root()->SetAttribute("model", options.model_name.c_str());
  composer.add(environment, env_doc.RootElement());
  composer.add(robot, robot_doc.RootElement());

  // Offscreen buffer large enough for rendering.
  XMLElement* visual = composer.section("visual");
  XMLElement* global = visual->FirstChildElement("global");
  if (!global) global = visual->InsertEndChild(composer.doc().NewElement("global"))->ToElement();
  global->SetAttribute("offwidth",
                       std::max(global->IntAttribute("offwidth"), options.offscreen_width));
  global->SetAttribute("offheight",
                       std::max(global->IntAttribute("offheight"), options.offscreen_height));

  // Each geom placed directly in the world (a room's floor, walls, window) goes on a static
  // body of its own with the world's frame, named as the geom is (unless a body has that
  // name): the same geom, pose and collisions. MuJoCo pairs the world body with every other
  // body and then visits each pair of their geoms, so seven room geoms on the world body cost
  // seven geom pairs per geom of every body at every step; on bodies of their own the walls
  // leave the broadphase while the physics' contact pruning closes them, and a floor plane is
  // visited once per geom.
  XMLElement* world = composer.section("worldbody");
  std::set<std::string> body_names;
  std::function<void(const XMLElement*)> collect = [&](const XMLElement* e) {
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::string(c->Name()) == "body" && c->Attribute("name")) {
        body_names.insert(c->Attribute("name"));
      }
      collect(c);
    }
  };
  collect(world);
  for (XMLElement* geom = world->FirstChildElement("geom"); geom;) {
    XMLElement* next = geom->NextSiblingElement("geom");
    XMLElement* body = composer.doc().NewElement("body");
    const char* name = geom->Attribute("name");
    if (name && body_names.insert(name).second) body->SetAttribute("name", name);
    world->InsertAfterChild(geom, body);
    body->InsertEndChild(geom);
    geom = next;
  }

  // Reserved obstacle slots: static bodies, one geom per shape, all disabled (no collision,
  // hidden in geom group 3) until a layout enables one.
  for (int slot = 0; slot < options.obstacle_slots; ++slot) {
    XMLElement* body = composer.doc().NewElement("body");
    body->SetAttribute("name", obstacle_body_name(slot).c_str());
    body->SetAttribute("pos", "0 0 -5");
    for (auto shape : {core::ObstacleShape::kBox, core::ObstacleShape::kCylinder,
                       core::ObstacleShape::kSphere}) {
      XMLElement* geom = composer.doc().NewElement("geom");
      geom->SetAttribute("name", obstacle_geom_name(slot, shape).c_str());
      geom->SetAttribute("type", core::to_string(shape));
      geom->SetAttribute("size", "0.05 0.05 0.05");
      geom->SetAttribute("contype", 0);
      geom->SetAttribute("conaffinity", 0);
      geom->SetAttribute("group", 3);
      geom->SetAttribute("rgba", "0.75 0.35 0.2 1");
      body->InsertEndChild(geom);
    }
    world->InsertEndChild(body);
  }

  tinyxml2::XMLPrinter printer;
  composer.doc().Print(&printer);
  return printer.CStr();
}

}  // namespace taskmatrix::mujoco
