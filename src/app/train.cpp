// `rdsim train`: the command line's settings handed to a Trainer (rdsim/training/trainer.hpp).
#include "rdsim/app/train.hpp"

#include <CLI/CLI.hpp>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/training/data_parallel.hpp"
#include "rdsim/training/process_communicator.hpp"

namespace rdsim {

int train_command(TrainerSettings settings) {
  // The MPI job this process is a rank of; after an error on one rank the others are stopped
  // instead of waiting for it in a collective.
  std::unique_ptr<Communicator> comm;
  auto stop = [&](int code) {
    if (comm && comm->size() > 1) comm->abort(code);
    return code;
  };
  try {
    comm = make_process_communicator();
    settings.communicator = comm.get();
    settings.handle_signals = true;
    Trainer trainer(std::move(settings));
    return trainer.run().exit_code;
  } catch (const RankExit& e) {  // rank 0 reports this error
    return e.job_knows ? e.code : stop(e.code);
  } catch (const JobError& e) {  // every rank knows: each returns, MPI finalises normally
    return report_error(e.what());
  } catch (const Error& e) {
    if (comm && comm->rank() > 0) return stop(report_error("(MPI rank " + std::to_string(comm->rank()) + ") " + e.what()));
    return stop(report_error(e.what()));
  } catch (...) {
    return stop(report_current_exception());
  }
}

Command train_command_entry() {
  return {"train",
          "Train a policy from a JSON config; writes progress.csv, episodes.csv, config.json, model.bin and "
          "checkpoint.bin to the run folder",
          [](CLI::App& cmd) -> std::function<int()> {
            struct Line {
              TrainerSettings settings;
              std::string seed, timesteps, log_dir;
              double max_memory = 0.0;
              int threads = 0;
            };
            auto l = std::make_shared<Line>();
            TrainerSettings& o = l->settings;
            auto* config = cmd.add_option("-c,--config", o.config_path, "JSON config file (see configs/; a relative path not found here is looked up in the configs rdsim carries)");
            auto* resume = cmd.add_option("--resume", o.resume_dir, "Continue the run in this folder from its last checkpoint");
            config->excludes(resume);
            resume->excludes(config);
            cmd.add_option("--seed", l->seed, "Override the config's seed (integer in [0, 2^64 - 1])")->type_name("INT");
            cmd.add_option("--timesteps", l->timesteps, "Override the config's total_timesteps (integer in [1, 1e12]); the run ends after the update that reaches it, so it "
                           "rounds up to whole updates (PPO, A2C, TRPO, BC: rollouts of n_steps x num_envs; ARS, CMA-ES: "
                           "whole episodes; the others: one step of every env), as the start and the summary say")->type_name("INT");
            cmd.add_option("--log-dir", l->log_dir, "Override the config's log_dir (the run folder)");
            cmd.add_flag("--overwrite", o.overwrite, "Delete another run's files in the run folder first (else refused)");
            cmd.add_option("--max-memory", l->max_memory,
                           "Memory limit in GB for the run's estimated needs (default: 80% of the machine's memory)")
                ->check(CLI::Range(0.001, 1e6).description("in [0.001, 1e6]"));
            cmd.add_option("--threads", l->threads,
                           "Override the config's num_threads (workers stepping the envs: threads, "
                           "or for pixel envs processes; results do not depend on it)")
                ->check(CLI::Range(1, 4096));
            cmd.add_flag("-q,--quiet", o.quiet, "No progress line (the summary line stays)");
            cmd.footer("Data-parallel on several processes or machines: mpirun -np K rdsim train --config FILE "
                       "(each rank its own envs; total_timesteps counts all ranks; rank 0 writes the run folder).");
            cmd.add_option("--dashboard", o.dashboard,
                           "Serve the live dashboard of this run at HOST:PORT while training (e.g. 127.0.0.1:8097)");
            return [l, &cmd] {
              TrainerSettings& s = l->settings;
              if (s.config_path.empty() && s.resume_dir.empty()) throw Error("train: give --config FILE or --resume DIR");
              if (!s.config_path.empty()) s.config_path = shipped_file(s.config_path);  // an installed rdsim's configs/
              if (cmd.count("--seed")) s.overrides.push_back({"--seed", "seed", l->seed});
              if (cmd.count("--timesteps")) s.overrides.push_back({"--timesteps", "total_timesteps", l->timesteps});
              if (cmd.count("--log-dir")) s.overrides.push_back({"--log-dir", "log_dir", l->log_dir});
              if (cmd.count("--max-memory")) s.max_memory_gb = l->max_memory;
              if (cmd.count("--threads")) s.threads = l->threads;
              return train_command(s);
            };
          }};
}

}  // namespace rdsim
