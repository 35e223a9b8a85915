#pragma once
#include <string>
#include <vector>

// `rdsim bench-learner`: what one learner update costs (src/bench/bench_learner.cpp). Each row
// times zero_grad + forward + backward + Adam step of the networks an algorithm trains, on fixed
// random inputs (drawn before the clock starts), float32:
//   ppo_mlp_<h>:     PPO's actor-critic on jaka_button (ground truth, Discrete actions): separate
//                    actor and critic MLPs [h, h], tanh; minibatch 512; loss = policy gradient +
//                    entropy bonus + value MSE (PPO's loss without the ratio clipping).
//   ppo_cnn_<preset>_<side>: PPO's pixel actor-critic: the small or Nature CNN trunk on side x side
//                    x 3 images (ReLU), two linear heads; batch 256; the same loss.
//   sac_critics:     SAC's critic pair on jaka_button (continuous actions): two Q MLPs [256, 256],
//                    ReLU, on observation + action; batch 256; loss = both critics' MSE.
// Per row: warm-up updates, then updates until `min_seconds` have passed (at least 3); the time
// per update of each run, median of `runs` runs. The matrix products run on the chosen GEMM backend
// (nn/gemm.hpp) with `threads` threads (oneDNN only; everything else runs on one thread). tools/bench/learner.py runs the same rows in
// PyTorch from the JSON (which describes every layer) and prints the ratios.
namespace rdsim {

struct BenchLearnerOptions {
  std::vector<std::string> rows;  // row names or prefixes ("ppo_mlp"); empty: all
  int runs = 3;
  double min_seconds = 0.5;       // per run
  std::string json_path;          // "-" for stdout; empty: no JSON
  bool list = false;              // print the row names and exit
  std::string gemm;               // "eigen" | "onednn"; empty: the build's default (nn/gemm.hpp)
  int threads = 1;                // threads of the oneDNN products (Eigen's: always one)
};

int bench_learner_command(const BenchLearnerOptions& options);

}  // namespace rdsim
