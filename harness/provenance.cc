#include "harness/provenance.h"

#include <openssl/evp.h>
#include <unistd.h>

#include <mujoco/mujoco.h>
#include <ompl/config.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

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

std::string executable_hash() {
  std::ifstream in("/proc/self/exe", std::ios::binary);
  if (!in) return "unknown";
  Sha256 sha;
  std::array<char, 1 << 16> buf{};
  while (in.read(buf.data(), buf.size()) || in.gcount() > 0) {
    sha.add(buf.data(), static_cast<size_t>(in.gcount()));
  }
  return sha.hex();
}

std::string ompl_version() {
  return std::to_string(OMPL_MAJOR_VERSION) + "." + std::to_string(OMPL_MINOR_VERSION) + "." +
         std::to_string(OMPL_PATCH_VERSION);
}

std::string mujoco_version() {
  const int v = mj_version();
  return std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
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
                               const std::vector<std::string>& command_line, int jobs) {
  nlohmann::json p;
  const std::string git = "git -C " + quoted(repo_root.string());
  const std::string commit = run_command(git + " rev-parse HEAD 2>/dev/null");
  p["git_commit"] = commit.empty() ? "unknown" : commit;
  p["git_dirty"] = commit.empty()
                       ? nlohmann::json(nullptr)
                       : nlohmann::json(!run_command(git + " status --porcelain "
                                                           "--untracked-files=no 2>/dev/null")
                                             .empty());
  p["mujoco_version"] = mujoco_version();
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
                         {"program", s.run.program},
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

nlohmann::json matrix_provenance(const RunPlan& plan, const RunOverrides& overrides,
                                 size_t trials) {
  return {{"file", std::filesystem::absolute(plan.file).lexically_normal().string()},
          {"trials", trials},
          {"overrides",
           {{"trials", overrides.trials > 0 ? nlohmann::json(overrides.trials) : nullptr},
            {"seed", overrides.seed > 0 ? nlohmann::json(overrides.seed) : nullptr},
            {"planners", overrides.planners}}}};
}

RunOverrides overrides_of(const nlohmann::json& matrix, const std::string& file) {
  RunOverrides o;
  try {
    const nlohmann::json& j = matrix.at("overrides");
    if (!j.at("trials").is_null()) o.trials = j.at("trials").get<int>();
    if (!j.at("seed").is_null()) o.seed = j.at("seed").get<std::uint32_t>();
    o.planners = j.at("planners").get<std::vector<std::string>>();
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError(file, "matrix.overrides", std::string("unreadable: ") + e.what());
  }
  return o;
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
