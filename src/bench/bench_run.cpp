#include "rdsim/bench/bench_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

Action random_action(const ActionSpace& space, Rng& rng) {
  if (space.discrete) return Action::discrete(static_cast<int>(rng.below(space.n)));
  Eigen::VectorXf v(space.low.size());
  for (int i = 0; i < v.size(); ++i) v[i] = static_cast<float>(rng.uniform(space.low[i], space.high[i]));
  return Action::continuous(std::move(v));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  if (n == 0) return 0.0;
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank > 0 ? rank - 1 : 0)];
}

double env_run(Env& env, long long steps, std::uint64_t seed, long long& episodes, std::vector<double>* step_seconds) {
  Rng rng = Rng::derive(seed, 1);
  const ActionSpace& space = env.spec().action;
  // Actions are drawn before the clock starts so the run measures the env alone.
  std::vector<Action> actions;
  actions.reserve(static_cast<size_t>(std::min<long long>(steps, 4096)));
  for (size_t i = 0; i < actions.capacity(); ++i) actions.push_back(random_action(space, rng));
  if (step_seconds) step_seconds->reserve(step_seconds->size() + static_cast<size_t>(steps));
  env.reset(seed);
  const auto t0 = Clock::now();
  for (long long i = 0; i < steps; ++i) {
    const auto before = step_seconds ? Clock::now() : t0;
    StepResult r = env.step(actions[static_cast<size_t>(i) % actions.size()]);
    if (step_seconds) step_seconds->push_back(std::chrono::duration<double>(Clock::now() - before).count());
    if (r.terminated || r.truncated) {
      env.reset();
      ++episodes;
    }
  }
  return static_cast<double>(steps) / std::chrono::duration<double>(Clock::now() - t0).count();
}

std::FILE* table_stream(const std::string& json_path) { return json_path == "-" ? stderr : stdout; }

void write_bench_json(const std::string& json_path, const nlohmann::json& results) {
  if (json_path == "-") {
    std::cout << results.dump(2) << "\n";
  } else if (!json_path.empty()) {
    write_file_atomic(json_path, results.dump(2) + "\n");
    std::printf("wrote %s\n", json_path.c_str());
  }
}

}  // namespace rdsim
