#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/training/setting_names.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/vecenv/episode_tracker.hpp"

// One training run: the loop every algorithm shares (rdsim/algorithms/algorithm.hpp), driven by
// `rdsim train`, the Python package and the tests alike (src/training/trainer.cpp).
//
//   Trainer trainer(settings);
//   trainer.start();                 // config, run folder, envs, algorithm; the first checkpoint
//   while (trainer.update()) {}      // one update each; false once the run is over or stopped
//   TrainResult r = trainer.finish();  // the last checkpoint and model; the summary
//
// run() does all three. Bad input throws rdsim::Error (under MPI: data_parallel.hpp's JobError /
// RankExit). A stop asked for by request_stop() (or, with handle_signals, by SIGINT/SIGTERM) ends
// the loop after the update in progress; finish() then saves checkpoint.bin and model.bin, from
// which `rdsim train --resume DIR` continues bit for bit.
namespace rdsim {

class Communicator;  // rdsim/parallel/communicator.hpp

struct TrainerSettings {
  std::string config_path;        // the config file; or, when empty, `config` below
  nlohmann::json config;          // a config as JSON (the file's contents), read by the same rules
  std::string resume_dir;         // continue the run in this folder from its last checkpoint
  // Run settings replacing the config's (seed, total_timesteps, log_dir), each read with the config
  // file's rules (train_config.hpp); set_seed() and friends add one.
  std::vector<ConfigOverride> overrides;
  std::optional<int> threads;     // replaces the config's num_threads
  bool overwrite = false;         // a new run may replace another run's files in its folder
  std::optional<double> max_memory_gb;  // the memory limit (memory_check.hpp); default: 80% of the machine's
  bool quiet = false;             // no progress line (the summary line stays)
  std::string dashboard;          // serve the live dashboard of the run at HOST:PORT while training
  // Whether SIGINT/SIGTERM ask the run to stop (interrupt.hpp), as in `rdsim train`. A host with
  // its own signal handling (Python) leaves it false and calls Trainer::request_stop.
  bool handle_signals = false;
  Communicator* communicator = nullptr;  // the MPI job this process is a rank of; null: one process
  SettingNames names;  // how messages spell these settings (the Python package sets names.python)

  void set_seed(std::uint64_t seed);
  void set_timesteps(long long timesteps);
  void set_log_dir(const std::string& dir);
};

// What a finished (or stopped) run did.
struct TrainResult {
  std::string run_dir;          // the run folder (rank 0; empty on other MPI ranks)
  std::string model_path;       // run_dir/model.bin
  std::string checkpoint_path;  // run_dir/checkpoint.bin
  long long timesteps = 0;      // env steps of the run (all ranks), including a resumed run's earlier ones
  long long total_timesteps = 0;
  long long episodes = 0;
  long long updates = 0;
  EpisodeStats stats;           // over the last stats_window episodes
  double wall_time = 0.0;       // seconds of env stepping and learning (VecEnv::wall_time)
  int stop_signal = 0;          // the signal that stopped the run early (SIGINT/SIGTERM); 0: ran to the end
  int exit_code = 0;            // `rdsim train`'s exit status: 0, or 128 + stop_signal
};

class Trainer {
public:
  explicit Trainer(TrainerSettings settings);
  ~Trainer();
  Trainer(const Trainer&) = delete;
  Trainer& operator=(const Trainer&) = delete;

  // Reads the config (or the checkpoint of resume_dir), checks its memory, takes the run folder,
  // builds the envs and the algorithm, learns from the demonstrations, writes config.json and (a
  // new run) the first checkpoint.
  void start();
  // One update of the algorithm, its rows in progress.csv and episodes.csv and a checkpoint when
  // one is due. False when the run is over (total_timesteps reached, or a stop was requested):
  // call finish(). Collective under MPI.
  bool update();
  // Writes checkpoint.bin and model.bin now (collective under MPI).
  void save();
  // Ends the run: compares the ranks' weights, saves, prints the summary line.
  TrainResult finish();
  // start(), update() until false, finish().
  TrainResult run();

  // Asks the run to stop after the update in progress, exactly as Ctrl-C does (exit code
  // 128 + signal). Safe from any thread and from a signal handler.
  void request_stop(int signal = 2 /* SIGINT */);

  // Between start() and finish() (finish() releases the run: its folder, envs and algorithm).
  const TrainConfig& config() const;
  long long timesteps() const;  // of the run, all ranks; 0 outside start() .. finish()
  bool started() const { return static_cast<bool>(run_); }

private:
  struct Run;  // everything start() builds
  int stop_signal() const;

  TrainerSettings settings_;
  std::atomic<int> stop_requested_{0};
  std::unique_ptr<Run> run_;
};

}  // namespace rdsim
