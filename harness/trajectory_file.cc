#include "harness/trajectory_file.h"

#include <zlib.h>

#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "harness/layout_json.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

constexpr const char* kMagic = "taskmatrix-trajectory 1\n";

struct GzCloser {
  void operator()(gzFile f) const {
    if (f) gzclose(f);
  }
};
using GzPtr = std::unique_ptr<gzFile_s, GzCloser>;

std::uint32_t bits_of(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

float float_of(std::uint32_t b) {
  float v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

}  // namespace

void write_trajectory_file(const std::filesystem::path& file, const TrajectoryFile& t) {
  const mujoco::StateRecording& r = t.recording;
  nlohmann::json header;
  header["robot"] = t.robot;
  header["environment"] = t.environment;
  header["layout_seed"] = t.layout.seed;
  nlohmann::json obstacles = nlohmann::json::array();
  for (const core::PlacedObstacle& o : t.layout.obstacles) {
    obstacles.push_back({{"shape", core::to_string(o.shape)},
                         {"region", o.region},
                         {"position", {o.position.x(), o.position.y(), o.position.z()}},
                         {"yaw", o.yaw},
                         {"size", {o.size.x(), o.size.y(), o.size.z()}},
                         {"footprint_radius", o.footprint_radius}});
  }
  header["obstacles"] = obstacles;
  if (!t.variation.empty()) header["variation"] = variation_json(t.variation);
  header["nq"] = r.nq;
  header["frame_period_s"] = r.frame_period_s;
  header["frames"] = r.frames();
  header["times"] = r.times;
  nlohmann::json removals = nlohmann::json::array();
  for (size_t k = 0; k < r.removals.size(); ++k) {
    removals.push_back({{"time_s", r.removals[k].time_s},
                        {"body", k < t.removed_bodies.size() ? t.removed_bodies[k] : ""}});
  }
  header["removals"] = removals;
  const std::string head = std::string(kMagic) + header.dump() + "\n";

  std::vector<std::uint32_t> words(r.qpos.size());
  const size_t nq = static_cast<size_t>(r.nq);
  for (size_t i = 0; i < words.size(); ++i) {
    const std::uint32_t b = bits_of(r.qpos[i]);
    words[i] = i >= nq ? b ^ bits_of(r.qpos[i - nq]) : b;
  }
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    GzPtr gz(gzopen(tmp.c_str(), "wb6"));
    if (!gz) throw std::runtime_error(tmp.string() + ": cannot open for writing");
    const bool ok =
        gzwrite(gz.get(), head.data(), static_cast<unsigned>(head.size())) ==
            static_cast<int>(head.size()) &&
        (words.empty() ||
         gzwrite(gz.get(), words.data(), static_cast<unsigned>(words.size() * sizeof(float))) ==
             static_cast<int>(words.size() * sizeof(float)));
    if (!ok) throw std::runtime_error(tmp.string() + ": write failed");
    if (gzclose(gz.release()) != Z_OK) throw std::runtime_error(tmp.string() + ": write failed");
  }
  std::filesystem::rename(tmp, file);
}

TrajectoryFile read_trajectory_file(const std::filesystem::path& file) {
  const std::string name = file.string();
  GzPtr gz(gzopen(name.c_str(), "rb"));
  if (!gz) throw core::InputError(name, "", "cannot open the trajectory file");
  std::string text;
  char buf[1 << 16];
  for (;;) {
    const int n = gzread(gz.get(), buf, sizeof buf);
    if (n < 0) throw core::InputError(name, "", "not a readable gzip file");
    if (n == 0) break;
    text.append(buf, static_cast<size_t>(n));
  }
  if (text.rfind(kMagic, 0) != 0) {
    throw core::InputError(name, "",
                           "not a taskmatrix trajectory (expected 'taskmatrix-trajectory 1')");
  }
  const size_t eol = text.find('\n', std::strlen(kMagic));
  if (eol == std::string::npos) throw core::InputError(name, "header", "truncated header");
  TrajectoryFile t;
  try {
    const nlohmann::json h =
        nlohmann::json::parse(text.substr(std::strlen(kMagic), eol - std::strlen(kMagic)));
    t.robot = h.at("robot").get<std::string>();
    t.environment = h.at("environment").get<std::string>();
    t.layout.seed = h.at("layout_seed").get<std::uint64_t>();
    for (const nlohmann::json& o : h.at("obstacles")) {
      core::PlacedObstacle p;
      const std::string shape = o.at("shape").get<std::string>();
      p.shape = shape == "box"        ? core::ObstacleShape::kBox
                : shape == "cylinder" ? core::ObstacleShape::kCylinder
                                      : core::ObstacleShape::kSphere;
      p.region = o.at("region").get<int>();
      const auto pos = o.at("position").get<std::vector<double>>();
      const auto size = o.at("size").get<std::vector<double>>();
      if (pos.size() != 3 || size.size() != 3) throw std::runtime_error("obstacle vectors");
      p.position = Eigen::Vector3d(pos[0], pos[1], pos[2]);
      p.size = Eigen::Vector3d(size[0], size[1], size[2]);
      p.yaw = o.at("yaw").get<double>();
      p.footprint_radius = o.at("footprint_radius").get<double>();
      t.layout.obstacles.push_back(p);
    }
    if (const auto v = h.find("variation"); v != h.end()) t.variation = variation_from_json(*v);
    t.recording.nq = h.at("nq").get<int>();
    t.recording.frame_period_s = h.at("frame_period_s").get<double>();
    t.recording.times = h.at("times").get<std::vector<double>>();
    for (const nlohmann::json& rm : h.at("removals")) {
      t.recording.removals.push_back({rm.at("time_s").get<double>(), -1});
      t.removed_bodies.push_back(rm.at("body").get<std::string>());
    }
    if (h.at("frames").get<size_t>() != t.recording.times.size() || t.recording.nq <= 0) {
      throw std::runtime_error("frame count and times disagree");
    }
  } catch (const std::exception& e) {
    throw core::InputError(name, "header", std::string("malformed: ") + e.what());
  }
  const size_t nq = static_cast<size_t>(t.recording.nq);
  const size_t count = t.recording.frames() * nq;
  if (text.size() - eol - 1 != count * sizeof(float)) {
    throw core::InputError(name, "frames",
                           "expected " + std::to_string(t.recording.frames()) + " frames of " +
                               std::to_string(nq) + " values: the file is truncated or corrupt");
  }
  std::vector<std::uint32_t> words(count);
  std::memcpy(words.data(), text.data() + eol + 1, count * sizeof(float));
  t.recording.qpos.resize(count);
  for (size_t i = 0; i < count; ++i) {
    if (i >= nq) words[i] ^= words[i - nq];
    t.recording.qpos[i] = float_of(words[i]);
  }
  return t;
}

}  // namespace taskmatrix::harness
