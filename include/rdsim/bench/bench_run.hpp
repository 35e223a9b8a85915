#pragma once
#include <cstdint>
#include <cstdio>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// The timed loop shared by the benchmarks (bench-fps, bench-remote): random actions drawn
// before the clock starts, resets included, as an agent would see the env.
namespace rdsim {

Action random_action(const ActionSpace& space, Rng& rng);

double median(std::vector<double> v);
// The q-quantile (0..1) of `v` (nearest rank).
double quantile(std::vector<double> v, double q);

// Steps `env` `steps` times from reset(seed), resetting after each episode (counted in
// `episodes`). Returns steps per second. With `step_seconds`, each step's duration is appended.
double env_run(Env& env, long long steps, std::uint64_t seed, long long& episodes,
               std::vector<double>* step_seconds = nullptr);

// Where a bench's table goes: stderr when its JSON goes to stdout (`json_path` "-"), so the JSON
// stays machine-readable; stdout otherwise.
std::FILE* table_stream(const std::string& json_path);
// The results as JSON: to stdout for "-", atomically to the file otherwise, nowhere for "".
void write_bench_json(const std::string& json_path, const nlohmann::json& results);

}  // namespace rdsim
