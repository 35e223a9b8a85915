#include "rdsim/training/memory_check.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sys/resource.h>
#include <unistd.h>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {
namespace {

constexpr double kShare = 0.8;  // of the memory there is, leaving room for the system and other jobs

// Address space the process already uses (code, libraries, heap), from /proc/self/statm.
double address_space_in_use() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0;
  if (!(statm >> pages)) return 0.0;
  return pages * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

}  // namespace

MemoryLimit memory_limit(std::optional<double> max_memory_gb, const SettingNames& names) {
  if (max_memory_gb) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%g", *max_memory_gb);
    return {*max_memory_gb * 1e9, names.with(Setting::MaxMemory, buf), names};
  }
  const double physical = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
  MemoryLimit limit{kShare * physical, "80% of this machine's " + format_bytes(physical), names};
  rlimit as{};
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const double left = static_cast<double>(as.rlim_cur) - address_space_in_use();
    if (kShare * left < limit.bytes)
      limit = {kShare * std::max(left, 0.0),
               "80% of the " + format_bytes(std::max(left, 0.0)) + " the address-space limit (ulimit -v) leaves", names};
  }
  return limit;
}

MemoryEstimate estimate_training_memory(const TrainConfig& config, const Spec& spec) {
  MemoryEstimate e;
  estimate_env_memory(config.env, config.num_envs, e);
  estimate_algorithm_memory(config.algorithm, spec, config.num_envs, e);
  return e;
}

void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& where) {
  if (estimate.total() <= limit.bytes) return;
  throw Error(where + ": this run would need " + estimate.summary() + "; more than the limit of " +
              format_bytes(limit.bytes) + " (" + limit.why + "): make those smaller, or raise the limit with " +
              limit.names.with(Setting::MaxMemory, "GB"));
}

}  // namespace rdsim
