// What an environment file says beyond its MJCF: where the robot starts, which bodies are
// task objects (by symbolic name), the visitor, and where random obstacles may go.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "taskmatrix/core/obstacle_layout.h"

namespace taskmatrix::core {

enum class ObjectKind { kGraspable, kTool, kSurface, kDebris };

struct ObjectSpec {
  std::string name;  // symbolic name programs use ("cup")
  ObjectKind kind = ObjectKind::kGraspable;
  std::vector<std::string> bodies;  // one body, or several for debris
  std::string tip_site;             // tools
  std::string grip_site;            // tools
};

struct VisitorSpec {
  std::string body;
  std::vector<std::array<double, 2>> path;  // waypoints on the floor
};

struct RobotStart {
  double x = 0, y = 0, yaw = 0;
};

struct EnvironmentSpec {
  std::string name;
  std::filesystem::path spec_file;
  std::filesystem::path model_file;
  RobotStart robot_start;
  double start_clearance_m = 0.6;
  std::map<std::string, ObjectSpec> objects;
  VisitorSpec visitor;
  std::vector<Rect2> keep_out;
  std::vector<ObstacleRegion> obstacle_regions;
  int obstacle_slots = 0;
  std::vector<std::string> cameras;
};

}  // namespace taskmatrix::core
