#include "harness/results/provenance.h"

#include <openssl/evp.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <ompl/config.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <thread>

#include "harness/results/build_info.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

std::string run_command(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return "";
  std::string out;
  std::array<char, 256> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string proc_field(const char* file, const std::string& key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) == 0) {
      const size_t colon = line.find(':');
      if (colon == std::string::npos) continue;
      std::string v = line.substr(colon + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      return v;
    }
  }
  return "";
}

class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr);
  }
  void add(const void* data, size_t size) { EVP_DigestUpdate(ctx_.get(), data, size); }
  std::string hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int size = 0;
    EVP_DigestFinal_ex(ctx_.get(), digest, &size);
    std::string out;
    char b[3];
    for (unsigned i = 0; i < size; ++i) {
      std::snprintf(b, sizeof b, "%02x", digest[i]);
      out += b;
    }
    return out;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

}  // namespace

std::string plan_hash(const RunPlan& plan) {
  Sha256 sha;
  auto add = [&](const std::string& name, const std::string& bytes) {
    sha.add(name.data(), name.size() + 1);  // with its NUL
    sha.add(bytes.data(), bytes.size());
    const char nul = 0;
    sha.add(&nul, 1);
  };
  const std::filesystem::path base = plan.file.parent_path();
  if (plan.suite) add(plan.file.filename().string(), plan.text);
  for (const Scenario& s : plan.scenarios) {
    add(std::filesystem::relative(s.file, base).generic_string(), s.file_text);
  }
  return sha.hex();
}

std::string file_sha256(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "";
  Sha256 sha;
  std::array<char, 1 << 16> buf{};
  while (in.read(buf.data(), buf.size()) || in.gcount() > 0) {
    sha.add(buf.data(), static_cast<size_t>(in.gcount()));
  }
  return sha.hex();
}

std::string executable_hash() {
  const std::string hash = file_sha256("/proc/self/exe");
  return hash.empty() ? "unknown" : hash;
}

std::string ompl_version() {
  return std::to_string(OMPL_MAJOR_VERSION) + "." + std::to_string(OMPL_MINOR_VERSION) + "." +
         std::to_string(OMPL_PATCH_VERSION);
}

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

std::string cpu_model() {
  const std::string m = proc_field("/proc/cpuinfo", "model name");
  return m.empty() ? "unknown" : m;
}

std::string utc_now_iso() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

nlohmann::json make_provenance(const RunPlan& plan, const std::filesystem::path& repo_root,
                               const std::vector<std::string>& command_line, int jobs,
                               const std::string& mujoco_version) {
  nlohmann::json p;
  // What ran: the build's commit, embedded when it was built.
  const std::string built_from = build_commit();
  p["git_commit"] = built_from;
  p["git_dirty"] =
      built_from == "unknown" ? nlohmann::json(nullptr) : nlohmann::json(build_dirty());
  p["build"] = {{"commit", built_from},
                {"dirty", p["git_dirty"]},
                {"diff_sha256", *build_diff_sha256() ? nlohmann::json(build_diff_sha256())
                                                     : nlohmann::json(nullptr)},
                {"describe", build_describe()},
                {"type", build_type()}};
  // Where the models and scenarios were read from: its own checkout, if it is one.
  const std::string git = "git -C " + quoted(repo_root.string());
  const std::string root_commit = run_command(git + " rev-parse HEAD 2>/dev/null");
  nlohmann::json root = {
      {"path", std::filesystem::absolute(repo_root).lexically_normal().string()}};
  if (root_commit.empty()) {
    root["git_commit"] = nullptr;
    root["git_dirty"] = nullptr;
    root["note"] = "not a git checkout: the model_files hashes identify its files";
  } else {
    root["git_commit"] = root_commit;
    root["git_dirty"] =
        !run_command(git + " status --porcelain --untracked-files=no 2>/dev/null").empty();
  }
  p["root"] = root;
  p["mujoco_version"] = mujoco_version;
  p["ompl_version"] = ompl_version();
  p["compiler"] = std::string("gcc-compatible ") + __VERSION__;
  p["executable_sha256"] = executable_hash();
  p["host"] = {{"name", host_name()},
               {"cpu", cpu_model()},
               {"cores", std::thread::hardware_concurrency()},
               {"memory", proc_field("/proc/meminfo", "MemTotal")}};
  p["run"] = plan.name;
  p["file"] = plan.file.string();
  p["scenario_hash"] = "sha256:" + plan_hash(plan);
  nlohmann::json scenarios = nlohmann::json::array();
  for (const Scenario& s : plan.scenarios) {
    nlohmann::json planners = nlohmann::json::array();
    for (const PlannerConfig& pc : s.planners) {
      planners.push_back({{"label", pc.label}, {"name", pc.spec.name}, {"params", pc.spec.params}});
    }
    scenarios.push_back({{"name", s.name},
                         {"file", s.file.string()},
                         {"file_sha256", file_sha256(s.file)},
                         {"program", s.run.program},
                         {"plan_time_limit_s", s.plan_time_limit_s},
                         {"layout_seed", s.layout_seed},
                         {"seed", s.seed},
                         {"trials", s.trials},
                         {"planners", planners}});
  }
  p["scenarios"] = scenarios;
  p["command_line"] = command_line;
  p["jobs"] = jobs;
  p["started_at"] = utc_now_iso();
  return p;
}

namespace {

std::string relative_to_root(const std::filesystem::path& file, const std::filesystem::path& root) {
  const std::filesystem::path abs = std::filesystem::absolute(file).lexically_normal();
  const std::filesystem::path rel =
      abs.lexically_relative(std::filesystem::absolute(root).lexically_normal());
  return !rel.empty() && *rel.begin() != ".." ? rel.generic_string() : abs.generic_string();
}

// Files an MJCF or URDF file names: MJCF `file` attributes (include, mesh, texture, hfield,
// skin; resolved against <compiler>'s assetdir/meshdir/texturedir) and URDF mesh `filename`s.
// Included MJCF files are followed.
void referenced_files(const std::filesystem::path& model, bool urdf,
                      std::vector<std::filesystem::path>& out, int depth = 0) {
  tinyxml2::XMLDocument doc;
  if (depth > 8 || doc.LoadFile(model.c_str()) != tinyxml2::XML_SUCCESS) return;
  const std::filesystem::path dir = model.parent_path();
  std::map<std::string, std::string> dirs;  // meshdir, texturedir, assetdir
  std::vector<const tinyxml2::XMLElement*> stack{doc.RootElement()};
  for (size_t i = 0; i < stack.size(); ++i) {
    for (const tinyxml2::XMLElement* e = stack[i]->FirstChildElement(); e;
         e = e->NextSiblingElement()) {
      stack.push_back(e);
      if (std::string(e->Name()) != "compiler") continue;
      for (const char* key : {"meshdir", "texturedir", "assetdir"}) {
        if (const char* v = e->Attribute(key)) dirs[key] = v;
      }
    }
  }
  for (const tinyxml2::XMLElement* e : stack) {
    if (e == nullptr) continue;
    const std::string name = e->Name();
    const char* file = e->Attribute(urdf ? "filename" : "file");
    if (file == nullptr || (urdf && name != "mesh")) continue;
    std::filesystem::path p = file;
    if (p.is_relative() && !urdf && name != "include") {
      const std::string key = name == "texture" ? "texturedir" : "meshdir";
      const std::string sub = dirs.count(key) ? dirs[key] : dirs["assetdir"];
      p = std::filesystem::path(sub) / p;
    }
    if (p.is_relative()) p = dir / p;
    out.push_back(p);
    if (!urdf && name == "include") referenced_files(p, false, out, depth + 1);
  }
}

}  // namespace

nlohmann::json model_files_provenance(const std::vector<LoadedModels>& scenes,
                                      const std::filesystem::path& root) {
  struct Entry {
    std::string role, of;
  };
  std::map<std::string, std::pair<std::filesystem::path, Entry>> files;  // by recorded path
  const auto add = [&](const std::filesystem::path& f, const std::string& role,
                       const std::string& of) {
    files.emplace(relative_to_root(f, root), std::pair{f, Entry{role, of}});
  };
  for (const auto& scene : scenes) {
    const core::RobotProfile& robot = *scene.robot;
    const core::EnvironmentSpec& env = *scene.environment;
    const bool urdf = robot.format == core::ModelFormat::kUrdf;
    add(robot.profile_file, "robot profile", robot.name);
    add(robot.model_file, urdf ? "robot model (URDF)" : "robot model (MJCF)", robot.name);
    add(env.spec_file, "environment spec", env.name);
    add(env.model_file, "environment model (MJCF)", env.name);
    std::vector<std::filesystem::path> assets;
    referenced_files(robot.model_file, urdf, assets);
    for (const auto& a : assets) add(a, "robot asset", robot.name);
    assets.clear();
    referenced_files(env.model_file, false, assets);
    for (const auto& a : assets) add(a, "environment asset", env.name);
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [path, file] : files) {
    const std::string hash = file_sha256(file.first);
    out.push_back({{"path", path},
                   {"role", file.second.role},
                   {"of", file.second.of},
                   {"sha256", hash.empty() ? nlohmann::json(nullptr) : nlohmann::json(hash)}});
  }
  return out;
}

nlohmann::json matrix_provenance(const RunPlan& plan, const RunOverrides& overrides,
                                 size_t trials) {
  return {{"file", std::filesystem::absolute(plan.file).lexically_normal().string()},
          {"trials", trials},
          {"overrides",
           {{"trials", overrides.trials > 0 ? nlohmann::json(overrides.trials) : nullptr},
            {"seed", overrides.seed > 0 ? nlohmann::json(overrides.seed) : nullptr},
            {"planners", overrides.planners},
            {"execution", overrides.execution.empty() ? nlohmann::json(nullptr)
                                                      : nlohmann::json(overrides.execution)},
            {"robots", overrides.robots},
            {"environments", overrides.environments}}}};
}

RunOverrides overrides_of(const nlohmann::json& matrix, const std::string& file) {
  RunOverrides o;
  try {
    const nlohmann::json& j = matrix.at("overrides");
    if (!j.at("trials").is_null()) o.trials = j.at("trials").get<int>();
    if (!j.at("seed").is_null()) o.seed = j.at("seed").get<std::uint32_t>();
    o.planners = j.at("planners").get<std::vector<std::string>>();
    // Recorded since 2026-12-06; a run directory written before has none of them.
    if (j.contains("execution") && !j.at("execution").is_null()) {
      o.execution = j.at("execution").get<std::string>();
    }
    if (j.contains("robots")) o.robots = j.at("robots").get<std::vector<std::string>>();
    if (j.contains("environments")) {
      o.environments = j.at("environments").get<std::vector<std::string>>();
    }
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError(file, "matrix.overrides", std::string("unreadable: ") + e.what());
  }
  return o;
}

std::optional<std::string> recorded_execution(const nlohmann::json& provenance) {
  if (!provenance.is_object()) return std::nullopt;
  const auto matrix = provenance.find("matrix");
  if (matrix == provenance.end() || !matrix->is_object()) return std::nullopt;
  const auto overrides = matrix->find("overrides");
  if (overrides == matrix->end() || !overrides->is_object()) return std::nullopt;
  const auto execution = overrides->find("execution");
  if (execution == overrides->end()) return std::nullopt;
  return execution->is_string() ? execution->get<std::string>() : std::string();
}

std::string execution_text(const std::string& execution) {
  return execution.empty() ? std::string("the scenarios' own execution modes")
                           : "--execution " + execution;
}

nlohmann::json slurm_provenance() {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, variable] :
       std::vector<std::pair<const char*, const char*>>{{"job_id", "SLURM_JOB_ID"},
                                                        {"array_job_id", "SLURM_ARRAY_JOB_ID"},
                                                        {"array_task_id", "SLURM_ARRAY_TASK_ID"},
                                                        {"cluster", "SLURM_CLUSTER_NAME"},
                                                        {"partition", "SLURM_JOB_PARTITION"},
                                                        {"nodes", "SLURM_JOB_NODELIST"}}) {
    if (const char* v = std::getenv(variable)) j[key] = v;
  }
  return j;
}

}  // namespace taskmatrix::harness
