#pragma once
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/parallel/communicator.hpp"

// The interface between the training loop (src/app/train.cpp) and a learning algorithm
// (PPO, A2C, DQN, SAC, TD3/DDPG, TRPO, ARS, CMA-ES, random). The loop owns the environments (a VecEnv, which also counts timesteps and
// tracks episodes), the log files and the model/checkpoint files; an algorithm owns its
// networks, optimiser and random streams, and decides how many env steps one update takes.
//
// The loop, in short:
//   auto algo = make_algorithm(config.algorithm, config.seed, envs.spec());  // algorithm_config.hpp
//   while (envs.timesteps() < total) {
//     Metrics m = algo->update(envs, {envs.timesteps(), total});   // steps envs, then learns
//     ... episodes.csv rows from envs.episodes().take_finished(), one progress.csv row from m ...
//   }
//   model.bin <- algo->save(out, /*training_state=*/false)
//
// Writing a new algorithm: step the envs ONLY through VecEnv::step (so timesteps and episode
// statistics stay right), use VecEnv::step results' `final_observation` to bootstrap on
// truncation (never on termination), draw all randomness from Rng streams derived with
// Rng::derive(config.seed, rng_stream::...) and save them in save(.., true). Start from what a
// family shares: OnPolicy (rollouts + GAE: PPO, A2C, TRPO), OffPolicy (replay of Box
// transitions: SAC, TD3/DDPG) or PolicySearch (candidates judged by whole episodes: ARS, CMA-ES).
namespace rdsim {

class VecEnv;                 // vec_env.hpp
struct DemoFile;              // demos/demo_file.hpp
struct DemonstrationsConfig;  // demonstrations.hpp
struct PolicyProgram;         // policy_program.hpp

// Named scalar statistics of one update, in a FIXED order for a given algorithm and config:
// they become the algorithm's columns of progress.csv (the first update fixes the header).
// Use snake_case names, e.g. {"policy_loss", x}, {"value_loss", y}, {"entropy", z}.
using Metrics = std::vector<std::pair<std::string, double>>;

// Where the run stands when an update starts; schedules (learning-rate annealing, exploration)
// are functions of it.
struct TrainProgress {
  long long timesteps = 0;        // env steps taken so far, all envs together
  long long total_timesteps = 1;  // the run's goal

  // 1 at the start of training, 0 at the end (Stable-Baselines3's "progress_remaining").
  double remaining(long long at_timesteps) const {
    const double r = 1.0 - static_cast<double>(at_timesteps) / static_cast<double>(total_timesteps);
    return r < 0.0 ? 0.0 : (r > 1.0 ? 1.0 : r);
  }

  // VecEnv steps of `num_envs` envs in a collection phase that wants `wanted` of them, starting
  // at `timesteps`: the last phase stops at the run's goal instead of overshooting it.
  long long phase_steps(long long wanted, int num_envs) const {
    const long long left = total_timesteps - timesteps;
    return left > 0 && (left + num_envs - 1) / num_envs < wanted ? (left + num_envs - 1) / num_envs : wanted;
  }
};

class Algorithm {
public:
  virtual ~Algorithm() = default;

  // The algorithm's name in configs: "ppo", "a2c", "dqn", "sac", "td3", "ddpg", "trpo", "ars", "cma_es", "random".
  virtual std::string name() const = 0;

  // Collects experience by stepping `envs` (as many steps as the algorithm's update needs,
  // e.g. n_steps per env for PPO) and improves the policy once. Returns this update's stats.
  virtual Metrics update(VecEnv& envs, const TrainProgress& progress) = 0;

  // The action for ONE observation: the most likely one when `deterministic` (replay), else a
  // draw from the policy using `rng`. Continuous actions are clipped to the action bounds.
  virtual Action act(const Observation& observation, bool deterministic, Rng& rng) = 0;

  // Binary state. training_state == false: what acting needs (network weights) -> model.bin.
  // training_state == true: everything an exact resume needs (weights, optimiser state, Rng
  // streams, counters) -> checkpoint.bin. load() throws rdsim::Error naming `source` when the
  // bytes do not fit this algorithm/config (the nn:: readers do that for tensors).
  virtual void save(std::ostream& out, bool training_state) const = 0;
  virtual void load(std::istream& in, bool training_state, const std::string& source) = 0;

  // Learning from demonstrations (the config's "demonstrations" object; what each algorithm does:
  // demonstrations.hpp). The training loop calls it once before the first update with `pretrain`
  // true, or on a resumed run with `pretrain` false (then an algorithm only takes back what it
  // uses during training, e.g. DQN's demonstration buffer). `demos` fit the env (demo_fit.hpp);
  // `rng` is the run's demonstrations stream. Returns one row per pre-training epoch
  // (-> pretrain.csv). The default: rdsim::Error, the algorithm cannot learn from demonstrations.
  virtual std::vector<Metrics> learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config,
                                                         Rng& rng, bool pretrain);

  // The deterministic policy as array operations (policy/policy_program.hpp), for `rdsim export`
  // and the policy part of model files. The default: rdsim::Error (the random agent has no policy).
  virtual PolicyProgram policy_program() const;
  // Whether policy_program() gives one (every algorithm but the random agent).
  virtual bool has_policy_program() const { return true; }

  // The config's "normalize_observations" (observation_normalizer.hpp): called once, right after
  // construction. The default: rdsim::Error (the config reader allows it for the algorithms that
  // override this).
  virtual void enable_observation_normalization();

  // Data-parallel training (`mpirun -np K rdsim train`): every rank runs this algorithm on its
  // own envs with the same initial weights, and the algorithm keeps the weights identical on all
  // ranks through `comm` (communicator.hpp): gradient methods average every gradient over the
  // ranks before their optimiser step (average_gradients, gradient_averaging.hpp); population
  // methods (ARS, CMA-ES) spread their population with allgather (population.hpp). Per-rank quantities (n_steps, buffer sizes,
  // learning_starts) stay per rank. Set before the first update; default: one process.
  void set_communicator(Communicator& comm) { comm_ = &comm; }
  // Whether the algorithm keeps the ranks identical through `comm` (above). The training loop
  // refuses an MPI run of one that does not (none of today's; check_data_parallel) rather than letting the
  // ranks drift apart. Default: no (a new algorithm opts in once it is wired).
  virtual bool data_parallel() const { return false; }
  // Whether every rank of an MPI job takes the same number of env steps in an update (the
  // gradient methods: n_steps, train_freq), so that the run's steps are K x a rank's. The
  // population methods' ranks run different whole episodes (policy_search.hpp).
  virtual bool lockstep() const { return true; }
  // The step count an update ends on: after every update a process's env steps are a multiple of
  // it, so the last update rounds total_timesteps up to one (the training loop says so). Default:
  // `num_envs` (one VecEnv step steps every env; the last collection phase stops at the goal,
  // TrainProgress::phase_steps). Whole rollouts: n_steps x num_envs. 0: no fixed multiple (whole
  // episodes, the population methods).
  virtual long long step_multiple(int num_envs) const { return num_envs; }
  // Every weight the ranks must share: rank 0 broadcasts them before the first update, and the
  // loop compares their hash across ranks. Default: the model (save/load without training state);
  // an algorithm whose model leaves out trained networks (critics, targets) adds them.
  virtual void save_all_weights(std::ostream& out) const { save(out, false); }
  virtual void load_all_weights(std::istream& in, const std::string& source) { load(in, false, source); }
  Communicator& communicator() const { return comm_ ? *comm_ : single_process_communicator(); }

private:
  Communicator* comm_ = nullptr;
};

}  // namespace rdsim
