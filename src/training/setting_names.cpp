#include "rdsim/training/setting_names.hpp"

namespace rdsim {
namespace {

struct Names {
  const char* cli;
  const char* python;
};

Names names_of(Setting s) {
  switch (s) {
    case Setting::Resume: return {"--resume", "resume"};
    case Setting::Overwrite: return {"--overwrite", "overwrite"};
    case Setting::LogDir: return {"--log-dir", "log_dir"};
    case Setting::Seed: return {"--seed", "seed"};
    case Setting::Timesteps: return {"--timesteps", "timesteps"};
    case Setting::MaxMemory: return {"--max-memory", "max_memory"};
  }
  return {"?", "?"};
}

// Paths are strings in Python; numbers (the other values) stay as written.
bool quoted(Setting s) { return s == Setting::Resume || s == Setting::LogDir; }

}  // namespace

std::string SettingNames::flag(Setting s) const {
  if (!python) return names_of(s).cli;
  return std::string(names_of(s).python) + (s == Setting::Overwrite ? "=True" : "=");
}

std::string SettingNames::with(Setting s, const std::string& value) const {
  if (!python) return std::string(names_of(s).cli) + " " + value;
  return std::string(names_of(s).python) + "=" + (quoted(s) ? "\"" + value + "\"" : value);
}

std::string SettingNames::resume_call(const std::string& dir, const std::string& more) const {
  if (!python) return "rdsim train " + with(Setting::Resume, dir) + (more.empty() ? "" : " " + more);
  return "rdsim.train(" + with(Setting::Resume, dir) + (more.empty() ? "" : ", " + more) + ")";
}

}  // namespace rdsim
