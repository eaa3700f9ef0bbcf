#include "harness/replay/trajectory_file.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "harness/results/json_input.h"
#include "harness/results/layout_json.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

constexpr const char* kMagic = "taskmatrix-trajectory 1\n";
constexpr std::uint64_t kMaxNq = 100000;
constexpr double kMaxTimeS = 1e6;        // simulated seconds
constexpr double kMaxCoordinate = 1000;  // metres
constexpr size_t kMaxBytes = size_t{1} << 30;

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
  const core::StateRecording& r = t.recording;
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
  const std::string head = std::string(kMagic) + json_text(header) + "\n";

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
    if (text.size() > kMaxBytes) throw core::InputError(name, "", "larger than 1 GiB unpacked");
  }
  if (text.rfind(kMagic, 0) != 0) {
    throw core::InputError(name, "",
                           "not a taskmatrix trajectory (expected 'taskmatrix-trajectory 1')");
  }
  const size_t eol = text.find('\n', std::strlen(kMagic));
  if (eol == std::string::npos) throw core::InputError(name, "header", "truncated header");
  TrajectoryFile t;
  const nlohmann::json h =
      parse_json_text(text.substr(std::strlen(kMagic), eol - std::strlen(kMagic)), name, 2);
  const JsonPlace where{name, 2, ""};
  if (!h.is_object()) where.fail("the header must be a JSON object");
  auto number = [](const nlohmann::json& object, const char* key, const JsonPlace& w) {
    return json_field(object, key, JsonKind::kNumber, w).get<double>();
  };
  t.robot = json_field(h, "robot", JsonKind::kString, where).get<std::string>();
  t.environment = json_field(h, "environment", JsonKind::kString, where).get<std::string>();
  t.layout.seed = json_field(h, "layout_seed", JsonKind::kUnsigned, where).get<std::uint64_t>();
  const nlohmann::json& obstacles = json_field(h, "obstacles", JsonKind::kArray, where);
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const JsonPlace ow = where.at("obstacles[" + std::to_string(i) + "]");
    const nlohmann::json& o = obstacles[i];
    core::PlacedObstacle p;
    const std::string shape = json_field(o, "shape", JsonKind::kString, ow).get<std::string>();
    if (shape != "box" && shape != "cylinder" && shape != "sphere") {
      ow.at("shape").fail("must be box, cylinder or sphere");
    }
    p.shape = shape == "box"        ? core::ObstacleShape::kBox
              : shape == "cylinder" ? core::ObstacleShape::kCylinder
                                    : core::ObstacleShape::kSphere;
    const std::uint64_t region =
        json_field(o, "region", JsonKind::kUnsigned, ow).get<std::uint64_t>();
    if (region > 1000) ow.at("region").fail("must be a region index (0..1000)");
    p.region = static_cast<int>(region);
    for (const char* key : {"position", "size"}) {
      const nlohmann::json& v = json_field(o, key, JsonKind::kArray, ow);
      if (v.size() != 3) ow.at(key).fail("must hold 3 numbers");
      Eigen::Vector3d x;
      for (int k = 0; k < 3; ++k) {
        if (!v[k].is_number() || !std::isfinite(v[k].get<double>()) ||
            std::abs(v[k].get<double>()) > kMaxCoordinate) {
          ow.at(key).fail("must hold 3 finite numbers (metres, |x| <= 1000)");
        }
        x[k] = v[k].get<double>();
      }
      (std::string(key) == "position" ? p.position : p.size) = x;
    }
    p.yaw = number(o, "yaw", ow);
    p.footprint_radius = number(o, "footprint_radius", ow);
    t.layout.obstacles.push_back(p);
  }
  if (const auto v = h.find("variation"); v != h.end()) {
    try {
      t.variation = variation_from_json(*v);
    } catch (const std::exception& e) {
      where.at("variation").fail(std::string("malformed: ") + e.what());
    }
  }
  const std::uint64_t values = json_field(h, "nq", JsonKind::kUnsigned, where).get<std::uint64_t>();
  if (values == 0 || values > kMaxNq) where.at("nq").fail("must be in 1..100000");
  t.recording.nq = static_cast<int>(values);
  t.recording.frame_period_s = number(h, "frame_period_s", where);
  const nlohmann::json& times = json_field(h, "times", JsonKind::kArray, where);
  for (size_t k = 0; k < times.size(); ++k) {
    // Simulated seconds, in order, within what a trial can last.
    const double v = times[k].is_number() ? times[k].get<double>() : NAN;
    if (!(std::isfinite(v) && v >= 0 && v <= kMaxTimeS) ||
        (k > 0 && v < t.recording.times.back())) {
      where.at("times[" + std::to_string(k) + "]")
          .fail("must be a time in [0, 1e6] s, not before the previous frame's");
    }
    t.recording.times.push_back(v);
  }
  const nlohmann::json& removals = json_field(h, "removals", JsonKind::kArray, where);
  for (size_t k = 0; k < removals.size(); ++k) {
    const JsonPlace rw = where.at("removals[" + std::to_string(k) + "]");
    t.recording.removals.push_back({number(removals[k], "time_s", rw), -1});
    t.removed_bodies.push_back(
        json_field(removals[k], "body", JsonKind::kString, rw).get<std::string>());
  }
  if (json_field(h, "frames", JsonKind::kUnsigned, where).get<std::uint64_t>() !=
      t.recording.times.size()) {
    where.at("frames").fail("disagrees with the number of times");
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
