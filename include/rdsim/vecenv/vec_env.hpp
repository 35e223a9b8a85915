#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/vecenv/episode_tracker.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/vecenv/env_process.hpp"
#include "rdsim/vecenv/worker_pool.hpp"

// Several instances of one environment stepped together, with automatic reset, a timestep
// counter and episode tracking. Every algorithm steps envs only through this, so timesteps,
// episodes.csv and progress statistics are the same for all.
//
// Threads: the envs are split into num_threads() contiguous blocks, block w always stepped by
// worker w of a persistent WorkerPool (worker 0 is the calling thread). Each env writes its
// observation straight into its column of observations() (Env::step_into), and everything that
// is shared (the timestep counter, the episode tracker) is updated on the calling thread after
// the workers finish, in env order: results are identical for any thread count.
//
// Processes (EnvWorkers::processes): block 0 is stepped on the calling thread as before, blocks
// 1..T-1 each in a child process of its own (EnvProcess), for envs that cannot share a process
// well (pixel envs: Mesa draws one frame at a time per process). Same results again: each env is
// the same object stepped with the same actions, wherever it runs.
namespace rdsim {

enum class EnvWorkers { threads, processes };

// What suits local envs made from `env` on several workers: processes for pixel observations drawn
// by the CPU renderer (osmesa: Mesa's llvmpipe draws one frame at a time per process), threads
// otherwise (cheaper to hand over; a GPU context, as "egl" may hold, must not be forked). Envs that
// hold connections (RemoteEnv) must stay in this process whatever this says.
EnvWorkers auto_env_workers(const EnvConfig& env);

// What one env did in a VecEnv step. When the episode ended (terminated || truncated), the env
// has already been reset: VecEnv::observations() holds the new episode's first observation and
// `final_observation` the observation that ended the old one (bootstrap from its value when
// truncated && !terminated; never when terminated).
// One cache line (or more) each: workers write the results of neighbouring envs side by side, and
// sharing a line would make two cores trade it on every step.
struct alignas(64) EnvStep {
  float reward = 0.0f;
  bool terminated = false;
  bool truncated = false;
  StepInfo info;
  Observation final_observation;  // only filled when the episode ended

  bool done() const { return terminated || truncated; }
  // True when the return must be bootstrapped from V(final_observation).
  bool bootstrap() const { return truncated && !terminated; }
};

class VecEnv {
public:
  // Env i is first reset with a seed drawn from Rng::derive(seed, rng_stream::env_base + i);
  // later resets continue that env's own stream. All envs must share one Spec. num_threads
  // (>= 1) is capped at the number of envs.
  VecEnv(std::vector<std::unique_ptr<Env>> envs, std::uint64_t seed, int stats_window = 20, int num_threads = 1,
         EnvWorkers workers = EnvWorkers::threads);
  // Destroys every env on the worker that stepped it: a pixel env's renderer releases its GL
  // context in the thread where it is current (an EGL context current in a finished thread
  // would never be freed).
  ~VecEnv();
  VecEnv(const VecEnv&) = delete;
  VecEnv& operator=(const VecEnv&) = delete;

  int size() const { return static_cast<int>(envs_.size()); }
  // Workers stepping the envs: threads, or (processes()) this thread and T-1 child processes.
  int num_threads() const { return processes_.empty() ? pool_.size() : static_cast<int>(processes_.size()) + 1; }
  bool processes() const { return !processes_.empty(); }
  const Spec& spec() const { return envs_.front()->spec(); }
  // Env i itself (e.g. to render it). Call it only between steps, from the thread that steps;
  // rdsim::Error for an env that lives in a worker process.
  Env& env(int i);

  // The current observation of every env (after any automatic reset), one column per env.
  const ObservationBatch& observations() const { return batch_; }
  // Env i's current observation, copied.
  Observation observation(int i) const;

  // Steps env i with actions[i] for every i; resets the envs whose episode ended.
  const std::vector<EnvStep>& step(const std::vector<Action>& actions);
  // Steps only the envs with active[i] (population methods, whose envs finish their share of
  // episodes at different times): the others keep their observation and episode, their action
  // is not used, their EnvStep is all zero, and they add no timesteps.
  const std::vector<EnvStep>& step(const std::vector<Action>& actions, const std::vector<bool>& active);

  // Pipelined stepping, EnvPool's asynchronous batches in a fixed order: the envs are cut into
  // groups() contiguous groups, group g = envs [g n / G, (g + 1) n / G). send(g, actions) starts
  // group g's step (actions[i] for its envs; the other entries are not read) and returns at once;
  // recv(g) waits for it and returns the results (entries of group g valid until the next recv or
  // step). While the caller acts on one group, the workers step the others, so no worker waits at a
  // barrier at the end of each batch step. Groups are sent and received in turn, 0, 1, ..., G-1,
  // 0, ...; every env gets the same actions as with step() in the same order, episodes are recorded
  // in env order with the timestep of their round (one step of every group) as step() records them,
  // so a caller that acts the same gets the same results on any thread count. Overlap needs envs
  // that steps_on_any_thread and more than one thread; otherwise recv() steps its group there and
  // then. step(), reset(), save(), load() and drop_caches() need every group received first.
  void set_groups(int groups);
  int groups() const { return groups_; }
  int group_first(int group) const { return group * size() / groups_; }
  int group_end(int group) const { return (group + 1) * size() / groups_; }
  void send(int group, const std::vector<Action>& actions);
  const std::vector<EnvStep>& recv(int group);
  // Groups sent and not yet received.
  int in_flight() const { return in_flight_; }

  // Starts a new episode in every env, env i seeded as at construction from Rng::derive(seed,
  // rng_stream::env_base + i) (so reset(seed) after VecEnv(envs, seed) repeats the first episodes);
  // the episodes in progress are dropped from the tracker. For callers that restart all envs at once
  // (the Python package's reset(seed=...)).
  void reset(std::uint64_t seed);

  long long timesteps() const { return timesteps_; }
  EpisodeTracker& episodes() { return tracker_; }
  const EpisodeTracker& episodes() const { return tracker_; }

  // Seconds of training so far (includes the time before a resume).
  double wall_time() const;

  // Brings every env's engine caches to the state a checkpoint restores (EnvCaches::drop_caches;
  // remote envs forward it to their server).
  // The training loop calls it at every update boundary, so a resumed run matches an
  // uninterrupted one bit for bit.
  void drop_caches();

  // Checkpoint support. When every env implements EnvState, save() stores their complete state
  // and load() continues bit-identically; otherwise load() resets the envs with fresh seeds and
  // drops the episodes that were in progress (returns false in that case).
  void save(std::ostream& out) const;
  bool load(std::istream& in, const std::string& source);

private:
  // Runs fn(first, end) for each worker's block of envs [first, end), on that worker.
  template <class Fn>
  void for_each_block(Fn fn);
  // Runs fn(i) for every env i, each on the worker that owns it.
  template <class Fn>
  void for_each_env(Fn fn);
  void step_block(int first, int end, const std::vector<Action>& actions, const std::vector<bool>& active);
  // Every env stepped once, each worker its own block first, then whatever the others have not
  // yet started (envs that steps_on_any_thread only): no worker waits while envs are left.
  void step_shared(const std::vector<Action>& actions, const std::vector<bool>& active);
  void finish_env(int i, const StepOutcome& outcome);
  // Runs this process's share (`local`) while the worker processes run the command started on
  // them, then waits for every process even after an error, so that all are idle again before the
  // first error (this process's, else the lowest block's) goes up.
  template <class Local>
  void alongside_processes(Local local);
  // reset (seeds) or step every env, worker processes and this thread side by side.
  void reset_all(std::uint64_t seed);
  void step_with_processes(const std::vector<Action>& actions, const std::vector<bool>& active);
  // Steps the envs with active[i] on whichever path suits them (shared, blocks or processes).
  void dispatch(const std::vector<Action>& actions, const std::vector<bool>& active);
  // The tracker's share of a step: envs [first, end) with active[i], stepped at `timestep`.
  void record(int first, int end, const std::vector<bool>& active, long long timestep);
  // Envs that any worker thread may step, and more than one thread: step() shares them out
  // (step_shared) and pipelined groups overlap.
  bool overlaps() const;
  // Pipelined groups: one env step claimed from the groups in flight, from group `first` on (worker
  // w's own part of each group first); the group it came from, or -1 when none is left to claim.
  int step_one_sent(int w, int first);
  void start_pipeline();
  void stop_pipeline();
  void require_idle(const char* what) const;
  std::vector<std::optional<std::string>> env_states() const;

  std::vector<std::unique_ptr<Env>> envs_;  // null where the env lives in a worker process
  int local_ = 0;                           // envs [0, local_) live in this process
  WorkerPool pool_;
  // step_shared: per worker, the next env of its block that no worker has started.
  struct alignas(64) NextEnv {
    std::atomic<int> index{0};
  };
  std::unique_ptr<NextEnv[]> next_env_;
  std::vector<std::unique_ptr<EnvProcess>> processes_;  // the blocks after the local one, in order
  std::vector<int> process_first_;                      // first env of each
  ObservationBatch batch_;
  std::vector<EnvStep> results_;
  // Per env: its step was begun (Env::begin_step). One cache line each, as workers write them side by side.
  struct alignas(64) Begun {
    bool value = false;
  };
  std::vector<Begun> begun_;
  std::vector<bool> all_active_;
  // Pipelined groups (send/recv).
  int groups_ = 1;
  std::vector<std::vector<bool>> group_active_;  // per group: its envs
  std::vector<Action> sent_actions_;               // per env: the action its group was sent with
  std::vector<std::exception_ptr> env_errors_;     // per env: what its pipelined step threw
  // Per group and worker, on lines of their own: env steps of the group that worker finished, ever
  // (never reset, so a send writes nothing the workers read but the claim indices).
  struct alignas(64) GroupProgress {
    std::atomic<long long> done{0};
  };
  std::unique_ptr<GroupProgress[]> group_done_;   // [group * workers + w]
  std::vector<long long> group_expected_;          // per group: its env steps sent, ever (the caller's)
  std::vector<bool> group_overlaps_;               // per group: its last send went to the workers
  std::unique_ptr<NextEnv[]> group_next_;  // [group * workers + w]: next unclaimed env of w's part
  int next_send_ = 0, next_recv_ = 0, in_flight_ = 0;
  long long round_base_ = 0;  // timesteps_ when the round's group 0 was received
  bool pipeline_running_ = false;
  alignas(64) std::atomic<std::uint64_t> posts_{0};  // bumped by every send and by the stop
  std::atomic<bool> stop_pipeline_{false};
  std::function<void(int)> pipeline_job_;
  EpisodeTracker tracker_;
  std::uint64_t seed_;
  long long timesteps_ = 0;
  double wall_offset_ = 0.0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace rdsim
