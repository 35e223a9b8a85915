#include "rdsim/training/evaluation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

#include "rdsim/training/policy_episodes.hpp"

namespace rdsim {

const std::vector<std::string>& Evaluation::columns() {
  // seconds last: the one column that differs between two runs of the same config and seed.
  static const std::vector<std::string> names = {"timesteps",  "episodes",    "mean_return",  "std_return", "min_return",
                                                 "max_return", "mean_length", "success_rate", "new_best",   "seconds"};
  return names;
}

Evaluation::Evaluation(const EvalConfig& config, std::unique_ptr<Env> env, std::uint64_t seed, const std::string& csv_path,
                       long long steps, const EvalState& state, bool resume)
    : every_(config.every),
      episodes_(config.episodes),
      env_(std::move(env)),
      seed_(seed),
      csv_(csv_path, columns(), resume ? state.rows : -1),
      best_(resume ? state.best_mean_return : EvalState{}.best_mean_return) {
  schedule_after(steps);
}

EvalResult Evaluation::run(long long steps, Algorithm& algo) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<EpisodeOutcome> outcomes = run_policy_episodes(*env_, algo, episodes_, seed_, true);
  EvalResult r;
  r.timesteps = steps;
  r.episodes = episodes_;
  r.min_return = outcomes.front().episode_return;
  r.max_return = outcomes.front().episode_return;
  for (const EpisodeOutcome& e : outcomes) {
    r.mean_return += e.episode_return;
    r.mean_length += static_cast<double>(e.length);
    r.success_rate += e.success ? 1.0 : 0.0;
    r.min_return = std::min(r.min_return, e.episode_return);
    r.max_return = std::max(r.max_return, e.episode_return);
  }
  const double n = static_cast<double>(outcomes.size());
  r.mean_return /= n;
  r.mean_length /= n;
  r.success_rate /= n;
  for (const EpisodeOutcome& e : outcomes) r.std_return += (e.episode_return - r.mean_return) * (e.episode_return - r.mean_return);
  r.std_return = std::sqrt(r.std_return / n);  // population sd, as SB3's evaluate_policy (np.std)
  r.new_best = r.mean_return > best_;
  if (r.new_best) best_ = r.mean_return;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  csv_.write_row({CsvWriter::cell(r.timesteps), CsvWriter::cell(r.episodes), CsvWriter::cell(r.mean_return),
                  CsvWriter::cell(r.std_return), CsvWriter::cell(r.min_return), CsvWriter::cell(r.max_return),
                  CsvWriter::cell(r.mean_length), CsvWriter::cell(r.success_rate), CsvWriter::cell(r.new_best),
                  CsvWriter::cell(r.seconds)});
  schedule_after(steps);
  return r;
}

std::string Evaluation::describe(const EvalResult& r) {
  char text[200];
  std::snprintf(text, sizeof text, "eval at %lld steps: mean return %.2f (sd %.2f), success %.2f, %d episode%s%s", r.timesteps,
                r.mean_return, r.std_return, r.success_rate, r.episodes, r.episodes == 1 ? "" : "s",
                r.new_best ? "; new best" : "");
  return text;
}

}  // namespace rdsim
