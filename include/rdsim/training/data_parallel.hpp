#pragma once
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/vecenv/episode_tracker.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/parallel/communicator.hpp"

// What `rdsim train` does differently as one rank of a data-parallel MPI job (mpirun -np K):
//  - rank r's envs and random streams use rank_seed(seed, r); the weights start as rank 0's;
//  - the algorithm averages its gradients over the ranks (Algorithm::set_communicator), and the
//    loop compares a hash of the weights across ranks every sync_check_interval updates;
//  - total_timesteps counts the env steps of all ranks (run_timesteps);
//  - rank 0 alone writes the run folder: episodes of every rank (RunEpisodes), progress,
//    config, model and one checkpoint holding every rank's state (gather_checkpoint), from which
//    `--resume` under the same K continues.
// With one process every function here is the plain single-process behaviour.
namespace rdsim {

// Rank 0: the config's seed (a one-rank job is the plain run); rank r > 0: one derived from it.
std::uint64_t rank_seed(std::uint64_t seed, int rank);

// The env steps of all ranks together (collective: one allgather). The gradient methods step in
// lockstep (K x this rank's); the population methods (ARS, CMA-ES) do not: their ranks run
// different episodes, so the training loop counts with this, the same number on every rank.
long long run_timesteps(Communicator& comm, const VecEnv& vec);

// Makes every rank's weights rank 0's (a fresh run: whatever each rank's seed drew).
void share_weights(Communicator& comm, Algorithm& algo);

// Refuses an MPI run (more than one rank) of an algorithm that does not keep the ranks identical
// (Algorithm::data_parallel): rdsim::Error on rank 0, while the other ranks wait in a collective
// that rank 0 never joins, until its report ends the job (main.cpp aborts it): one message.
void check_data_parallel(Communicator& comm, const Algorithm& algo);

// Compares a hash of the weights (Algorithm::save_all_weights) across the ranks.
// On a mismatch rank 0 throws rdsim::Error naming the first rank that differs and the update;
// the other ranks throw RankExit (rank 0 reports it).
void check_same_weights(Communicator& comm, const Algorithm& algo, long long updates);

// Thrown by ranks other than 0 for an error that rank 0 reports: exit quietly with `code`.
// `job_knows`: every rank knows of the error and leaves (JobError below), so the job ends
// without MPI_Abort (whose banner and killed ranks add noise); else rank 0 aborts the job.
struct RankExit {
  int code = 1;
  bool job_knows = false;
};

// An error that every rank of the job knows of: rank 0 throws it, the others RankExit{1, true}.
// main.cpp reports it once and returns its code on every rank, without MPI_Abort.
class JobError : public Error {
public:
  using Error::Error;
};

// Runs `step` on every rank (a step that may fail on some, e.g. rank 0's reading of the config
// file) and agrees on the outcome (collective: one allgather, plus a gather after a failure).
// When `step` threw rdsim::Error on any rank, rank 0 throws JobError with its own message or
// else the first failing rank's (naming that rank), and every other rank RankExit{1, true}: one
// message however many ranks failed. One process: `step` runs and its errors pass unchanged.
void on_every_rank(Communicator& comm, const std::function<void()>& step);

// The run's episode log. One process: the VecEnv's own tracker. Several: each update, every
// rank's finished episodes go to rank 0 in rank order, and are numbered there, with timesteps
// counted over all ranks: local timesteps x K when the ranks step in lockstep
// (Algorithm::lockstep); else (ARS, CMA-ES: whole episodes only) the run's steps before the
// update plus the lengths of the update's episodes up to this one in log order, so the column
// rises and ends the update at the run's steps.
class RunEpisodes {
public:
  RunEpisodes(Communicator& comm, int window, bool lockstep = true);

  // Takes this rank's finished episodes; returns the run's new ones (rank 0; empty elsewhere).
  // `steps_before`: the run's steps before this update (run_timesteps).
  std::vector<EpisodeRecord> take_finished(VecEnv& vec, long long steps_before);
  // Over the run's last `window` episodes / the number so far (rank 0).
  EpisodeStats stats(const VecEnv& vec) const;
  long long episodes(const VecEnv& vec) const;

  void save(std::ostream& out) const;  // several ranks only (part of the checkpoint)
  void load(std::istream& in, const std::string& source);

private:
  Communicator& comm_;
  bool lockstep_;
  EpisodeTracker merged_;  // several ranks: rank 0's log of every rank's episodes
};

// checkpoint.bin's payload for a K-rank job, assembled on rank 0 (collective; empty string on
// the other ranks). Layout: rank 0's `payload` exactly as a single process writes it (so
// `rdsim replay checkpoint.bin` reads the weights first), then for K > 1 an extension:
//   u32 K | bytes RunEpisodes | K-1 x bytes (ranks 1..K-1's payloads) | u64 extension size | "RDSIMMPI"
std::string gather_checkpoint(Communicator& comm, const std::string& payload, const RunEpisodes& episodes);

// This rank's payload from a checkpoint's (every rank holds the whole file). rdsim::Error naming
// `source` when the checkpoint's rank count differs from the job's. `episodes` (K > 1) is loaded.
std::string checkpoint_part(Communicator& comm, const std::string& payload, RunEpisodes& episodes,
                            const std::string& source);

}  // namespace rdsim
