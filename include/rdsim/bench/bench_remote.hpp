#pragma once
#include <string>

// `rdsim bench-remote`: what the network link costs (src/bench/bench_remote.cpp). In one process it
// starts an `rdsim serve` engine on a free loopback port (CurveZMQ on, fresh keys in a temporary
// folder), then measures, each as the median of `runs` runs:
//   - in-process steps/s of the env (random actions, resets included, as bench-fps);
//   - the same through one RemoteEnv client: steps/s and per-step round-trip latency p50/p99;
//   - both again with raw-pixel observations of image_size x image_size;
//   - `clients` RemoteEnv clients at once (one thread each): total steps/s against one client;
//   - one client stepping a VecEnv of `envs` remote envs on one thread (as `rdsim train` does: all
//     their requests in flight at once), ground truth and pixels, against the same VecEnv of
//     local envs.
namespace rdsim {

struct BenchRemoteOptions {
  std::string env = "jaka_button";
  long long steps = 20000;   // per client per run
  int clients = 4;
  int envs = 8;              // envs of the VecEnv rows; 1: no such rows
  int image_size = 64;
  int runs = 3;
  bool insecure = false;     // plain text instead of CurveZMQ
  std::string json_path;     // "-" for stdout; empty: no JSON
};

int bench_remote_command(const BenchRemoteOptions& options);

}  // namespace rdsim
