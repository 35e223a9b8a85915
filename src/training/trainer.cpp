// The one training loop for every algorithm (see include/rdsim/algorithms/algorithm.hpp).
#include "rdsim/training/trainer.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include "demonstration_pretraining.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/dashboard/dashboard_server.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/policy/policy_file.hpp"
#include "rdsim/policy/policy_program.hpp"
#include "rdsim/tensorboard/event_writer.hpp"
#include "rdsim/training/checkpoint.hpp"
#include "rdsim/training/data_parallel.hpp"
#include "rdsim/training/env_source.hpp"
#include "rdsim/training/evaluation.hpp"
#include "rdsim/training/interrupt.hpp"
#include "rdsim/training/progress_display.hpp"
#include "rdsim/training/run_dashboard.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "run_start.hpp"

namespace rdsim {
namespace {

const std::vector<std::string> episode_columns = {"episode", "timesteps", "return", "length", "success", "collision", "out_of_bounds", "wall_time"};
const std::vector<std::string> progress_head = {"timesteps", "updates", "episodes", "mean_return", "min_return",
                                                "max_return", "mean_length", "success_rate"};
// Last, so that comparing two runs can simply drop them: they are the only non-reproducible columns.
const std::vector<std::string> progress_tail = {"steps_per_s", "wall_time"};

std::vector<std::string> episode_row(const EpisodeRecord& e) {
  return {CsvWriter::cell(e.episode), CsvWriter::cell(e.timesteps), CsvWriter::cell(e.episode_return),
          CsvWriter::cell(e.length),  CsvWriter::cell(e.success),   CsvWriter::cell(e.collision),
          CsvWriter::cell(e.out_of_bounds), CsvWriter::cell(e.wall_time)};
}

// What the ranks agree on after each update, so that they leave the loop and save together:
// the largest stop signal any rank received (0: none) and whether rank 0's checkpoint
// schedule (which reads its own clock) says a save is due. One process: its own values.
struct LoopDecision {
  int signal = 0;
  bool save_due = false;
};

LoopDecision agree(Communicator& comm, int signal, bool save_due) {
  if (comm.size() == 1) return {signal, save_due};
  const std::uint64_t mine[2] = {static_cast<std::uint64_t>(signal), save_due ? 1u : 0u};
  std::vector<std::uint64_t> all(2 * static_cast<std::size_t>(comm.size()));
  comm.allgather(mine, 2, all.data());
  LoopDecision d;
  d.save_due = all[1] != 0;  // rank 0's schedule
  for (int r = 0; r < comm.size(); ++r) d.signal = std::max(d.signal, static_cast<int>(all[2 * static_cast<std::size_t>(r)]));
  return d;
}

// The step count a run of `total` steps ends on: the loop stops after the first update that reaches
// `total`, and every update ends on a multiple of `multiple` steps per rank (Algorithm::
// step_multiple; 0: none known in advance). Ranks in lockstep take the same steps each.
long long planned_timesteps(long long total, long long multiple, int ranks) {
  if (multiple <= 0) return total;
  const long long all = multiple * ranks;
  return (total + all - 1) / all * all;
}

// "20480 timesteps (total_timesteps 20000 rounded up to whole rollouts of ...)".
std::string summary_steps(long long steps, long long total, const std::string& rounding) {
  std::string text = std::to_string(steps) + " timesteps";
  if (steps > total)
    text += " (total_timesteps " + std::to_string(total) + " rounded up to " +
            (rounding.empty() ? std::string("whole episodes") : rounding) + ")";
  return text;
}

// "last 100 episodes: success 0.93, mean return -36.56".
std::string summary_stats(const EpisodeStats& s) {
  if (s.count == 0) return "no episode ended";
  char text[160];
  std::snprintf(text, sizeof text, "last %d episode%s: success %.2f, mean return %.2f", s.count, s.count == 1 ? "" : "s",
                s.success_rate, s.mean_return);
  return text;
}

// What one update's steps are, for the start note and the summary.
std::string update_unit(long long multiple, int num_envs) {
  if (multiple == num_envs) return "whole steps of all " + std::to_string(num_envs) + " envs";
  return "whole rollouts of " + std::to_string(multiple) + " steps (n_steps x num_envs)";
}

}  // namespace

void TrainerSettings::set_seed(std::uint64_t seed) { overrides.push_back({"seed", "seed", std::to_string(seed)}); }
void TrainerSettings::set_timesteps(long long timesteps) {
  overrides.push_back({"timesteps", "total_timesteps", std::to_string(timesteps)});
}
void TrainerSettings::set_log_dir(const std::string& dir) { overrides.push_back({"log_dir", "log_dir", dir}); }

// Declared in the order they are made, so they are destroyed in reverse: the logs are closed
// before the envs and the algorithm go, and the folder's lock is the last thing released.
struct Trainer::Run {
  std::optional<InterruptGuard> interrupts;  // with handle_signals
  Communicator* comm = nullptr;
  bool root = true;  // rank 0 holds and writes the run folder
  int ranks = 1;
  RunStart start;
  bool resume = false;
  std::unique_ptr<VecEnv> vec;
  std::optional<nn::GemmScope> gemm;  // the learner's backend and threads while the run lasts
  std::unique_ptr<Algorithm> algo;
  std::unique_ptr<RunEpisodes> run_episodes;
  TrainerState state;
  nlohmann::json resolved;
  std::unique_ptr<DashboardServer> dashboard;     // rank 0, with a dashboard address
  std::unique_ptr<CsvWriter> episodes, progress;  // rank 0; progress's columns are known after the first update
  std::unique_ptr<EventWriter> tensorboard;       // rank 0: progress.csv's scalars as TensorBoard event files
  std::unique_ptr<Evaluation> eval;               // rank 0, with "eval"
  // total_timesteps counts the steps of all ranks (the gradient methods' ranks step in lockstep,
  // each its share; the population methods' do not). `steps`: the run's, the same on every rank.
  long long total = 0, rank_total = 0, steps = 0;
  // The steps the run ends on: total rounded up to whole updates (planned_timesteps), and how.
  long long target = 0;
  std::string rounding;  // "whole rollouts of 2048 steps (n_steps x num_envs)"; empty: whole episodes
  std::optional<CheckpointSchedule> schedule;
  std::optional<ProgressDisplay> display;
  long long start_steps = 0, last_steps = 0;
  double start_wall = 0.0, last_wall = 0.0, overall_sps = 0.0;
  long long last_allreduce_bytes = 0;
  LoopDecision decision;

  std::string file(const std::string& name) const { return start.folder->file(name); }  // rank 0
  // Collective under MPI: every rank calls it, rank 0 writes the file.
  void save_file(const std::string& name, ModelKind kind);
  void write_progress(const Metrics& metrics, long long allreduce_bytes, double sps, double wall);
  // Rank 0: one evaluation (eval.csv, TensorBoard, best_model.bin when it is the best so far).
  void evaluate();
};

void Trainer::Run::save_file(const std::string& name, ModelKind kind) {
  ModelFile f;
  f.kind = kind;
  f.config = resolved;
  f.spec = describe_spec(vec->spec());
  // The policy alone, for controllers that link only rdsim_policy (policy/policy.hpp).
  if (root && algo->has_policy_program()) f.policy = encode_policy_program(algo->policy_program());
  if (kind == ModelKind::Model) {
    if (!root) return;
    std::ostringstream out;
    algo->save(out, false);
    f.payload = out.str();
  } else {
    if (root) {
      state.progress_rows = progress ? progress->rows() : state.progress_rows;
      state.episode_rows = episodes->rows();
      if (eval) state.eval = eval->state();
    }
    f.payload = gather_checkpoint(*comm, checkpoint_payload(*algo, *vec, state), *run_episodes);
    if (!root) return;
  }
  write_model_file(file(name), f);
}

// Rank 0: progress.csv's row of this update, and the progress line.
void Trainer::Run::write_progress(const Metrics& metrics, long long allreduce_bytes, double sps, double wall) {
  if (!progress) {
    std::vector<std::string> columns = progress_head;
    for (const auto& [name, value] : metrics) columns.push_back(name);
    if (ranks > 1) columns.push_back("allreduce_bytes");
    columns.insert(columns.end(), progress_tail.begin(), progress_tail.end());
    progress = std::make_unique<CsvWriter>(file(progress_csv_name), columns, resume ? state.progress_rows : -1);
  }
  const EpisodeStats s = run_episodes->stats(*vec);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> row = {CsvWriter::cell(steps),
                                  CsvWriter::cell(state.updates),
                                  CsvWriter::cell(run_episodes->episodes(*vec)),
                                  CsvWriter::cell(s.count ? s.mean_return : nan),
                                  CsvWriter::cell(s.count ? s.min_return : nan),
                                  CsvWriter::cell(s.count ? s.max_return : nan),
                                  CsvWriter::cell(s.count ? s.mean_length : nan),
                                  CsvWriter::cell(s.count ? s.success_rate : nan)};
  for (const auto& [name, value] : metrics) row.push_back(CsvWriter::cell(value));
  if (ranks > 1) row.push_back(CsvWriter::cell(allreduce_bytes));  // this rank's payload, this update
  row.push_back(CsvWriter::cell(sps));
  row.push_back(CsvWriter::cell(wall));
  progress->write_row(row);
  tensorboard->scalars(steps, scalars_of_row(progress->columns(), row));
  tensorboard->flush();
  overall_sps = wall > start_wall ? static_cast<double>(steps - start_steps) / (wall - start_wall) : 0.0;
  display->show(steps, target, s, overall_sps, wall);
}

void Trainer::Run::evaluate() {
  const EvalResult e = eval->run(steps, *algo);
  state.eval = eval->state();
  if (e.new_best) save_file(best_model_file_name, ModelKind::Model);
  tensorboard->scalars(steps, {{"eval/mean_return", e.mean_return},
                               {"eval/success_rate", e.success_rate},
                               {"eval/mean_length", e.mean_length}});
  tensorboard->flush();
  display->note(Evaluation::describe(e) + (e.new_best ? " -> " + file(best_model_file_name) : std::string()));
}

Trainer::Trainer(TrainerSettings settings) : settings_(std::move(settings)) {}
Trainer::~Trainer() = default;

void Trainer::request_stop(int signal) { stop_requested_.store(signal > 0 ? signal : 2); }

int Trainer::stop_signal() const {
  const int own = stop_requested_.load();
  return run_ && run_->interrupts ? std::max(own, run_->interrupts->requested()) : own;
}

const TrainConfig& Trainer::config() const {
  if (!run_) throw Error("Trainer: config() before start()");
  return run_->start.config;
}

long long Trainer::timesteps() const { return run_ ? run_->steps : 0; }

void Trainer::start() {
  if (run_) throw Error("Trainer: start() called twice");
  auto run = std::make_unique<Run>();
  Run& r = *run;
  // Before anything slow: a Ctrl-C during setup still saves or quits cleanly.
  if (settings_.handle_signals) r.interrupts.emplace();
  Communicator& comm = settings_.communicator ? *settings_.communicator : single_process_communicator();
  r.comm = &comm;
  r.root = comm.rank() == 0;
  r.ranks = comm.size();
  r.start = start_run(settings_, comm);
  TrainConfig& config = r.start.config;  // open_envs records a remote env's resolved values in it
  r.resume = !settings_.resume_dir.empty();

  const std::uint64_t seed = rank_seed(config.seed, comm.rank());
  std::shared_ptr<const DemoFile> demos;  // read once: the pre-training's and (without start_file) the envs' starts
  on_every_rank(comm, [&] {  // an env or algorithm that refuses the config: one message
    const nn::GemmBackend backend = resolve_gemm(config);
    if (config.algorithm.demonstrations) demos = std::make_shared<const DemoFile>(read_demonstrations(config));
    r.vec = std::make_unique<VecEnv>(open_envs(config, starting_demonstrations(config, demos)), seed, config.stats_window,
                                     resolve_num_threads(config, comm.local_size()), resolve_env_workers(config));
    r.vec->set_groups(std::min(config.env_groups, r.vec->size()));
    // The env workers wait while the learner updates, so it may use as many threads (the results
    // do not depend on it: nn/gemm.hpp).
    r.gemm.emplace(backend, r.vec->num_threads());
    r.algo = make_algorithm(config.algorithm, seed, r.vec->spec());
  });
  r.algo->set_communicator(comm);
  check_data_parallel(comm, *r.algo);
  r.run_episodes = std::make_unique<RunEpisodes>(comm, config.stats_window, r.algo->lockstep());
  if (r.resume) {
    const std::string& path = r.start.checkpoint_path;
    check_model_spec(r.start.checkpoint, r.vec->spec(), path);
    r.state = restore_checkpoint(checkpoint_part(comm, r.start.checkpoint.payload, *r.run_episodes, path), *r.algo, *r.vec,
                                 path, r.root, config.eval.has_value());
    r.start.checkpoint.payload.clear();
    if (r.root) {
      check_log_rows(r.file(progress_csv_name), r.state.progress_rows, path);
      check_log_rows(r.file(episodes_csv_name), r.state.episode_rows, path);
      if (r.state.eval) check_log_rows(r.file(eval_csv_name), r.state.eval->rows, path);
    }
  } else if (config.eval) {
    r.state.eval = EvalState{};
  }
  // Under MPI every rank learns from the demonstrations (the same draws: the stream is the run's,
  // not the rank's) and rank 0 writes pretrain.csv.
  if (config.algorithm.demonstrations)
    learn_from_demonstrations(config, *demos, *r.algo, r.vec->spec(), r.resume,
                              r.root ? r.start.folder->path() : std::filesystem::path(), settings_.quiet || !r.root);
  if (!r.resume) share_weights(comm, *r.algo);

  r.resolved = to_json(config);
  if (r.root) {
    write_file_atomic(r.file(run_config_name), r.resolved.dump(2) + "\n");
    // reads the run's files only
    r.dashboard = start_run_dashboard(settings_.dashboard, r.start.folder->path().string(), settings_.quiet);
    r.episodes = std::make_unique<CsvWriter>(r.file(episodes_csv_name), episode_columns, r.resume ? r.state.episode_rows : -1);
  }
  r.total = config.total_timesteps;
  r.rank_total = (r.total + r.ranks - 1) / r.ranks;
  r.steps = run_timesteps(comm, *r.vec);
  // The evaluation env is a local one, as `rdsim replay` uses (config.env holds a server's values).
  if (r.root && config.eval)
    r.eval = std::make_unique<Evaluation>(*config.eval, open_env(config.env, RemoteEnvConfig{}), config.seed,
                                          r.file(eval_csv_name), r.steps, *r.state.eval, r.resume);
  const long long multiple = r.algo->lockstep() ? r.algo->step_multiple(r.vec->size()) : 0;
  r.target = std::max(planned_timesteps(r.total, multiple, r.ranks), r.steps);
  if (multiple > 0) r.rounding = update_unit(multiple, r.vec->size()) + (r.ranks > 1 ? " on each of " + std::to_string(r.ranks) + " ranks" : "");
  if (r.root && !settings_.quiet && r.target != r.total && r.steps < r.total)
    std::fprintf(stderr, "rdsim train: total_timesteps %lld rounds up to %lld: an update takes %s\n", r.total, r.target,
                 r.rounding.c_str());
  if (r.root) {
    r.tensorboard = std::make_unique<EventWriter>(r.start.folder->path().string());
    // A resumed run: TensorBoard drops the earlier files' points after the checkpoint (the rows
    // progress.csv dropped), keeping the checkpoint's own row at `steps`.
    if (r.resume) r.tensorboard->session_start(r.steps + 1);
  }
  r.schedule.emplace(config.checkpoint_interval, config.checkpoint_seconds, r.steps);
  run_ = std::move(run);
  if (!r.resume) save();  // from the start, `--resume` always finds something to continue

  r.display.emplace(settings_.quiet || !r.root);
  r.start_steps = r.last_steps = r.steps;
  r.start_wall = r.last_wall = r.vec->wall_time();
  r.last_allreduce_bytes = comm.allreduce_traffic().bytes;
  r.decision = agree(comm, stop_signal(), false);
}

bool Trainer::update() {
  if (!run_) throw Error("Trainer: update() before start()");
  Run& r = *run_;
  if (r.steps >= r.total || r.decision.signal) return false;
  Communicator& comm = *r.comm;
  // One process: a stop asked for between updates ends the run before the next one. Under MPI the
  // ranks agree on it after the update (agree below), so that they all leave together.
  if (comm.size() == 1 && stop_signal()) {
    r.decision.signal = stop_signal();
    return false;
  }
  VecEnv& vec = *r.vec;
  vec.drop_caches();  // every update starts from what a checkpoint restores (core/env_state.hpp)
  const Metrics metrics = r.algo->update(vec, {vec.timesteps(), r.rank_total});
  const long long steps_before = r.steps;
  r.steps = run_timesteps(comm, vec);
  ++r.state.updates;
  for (const auto& e : r.run_episodes->take_finished(vec, steps_before)) r.episodes->write_row(episode_row(e));
  const TrainConfig& config = r.start.config;
  if (config.sync_check_interval > 0 && r.state.updates % config.sync_check_interval == 0)
    check_same_weights(comm, *r.algo, r.state.updates);
  const long long allreduce_bytes = comm.allreduce_traffic().bytes - r.last_allreduce_bytes;
  r.last_allreduce_bytes = comm.allreduce_traffic().bytes;

  const double wall = vec.wall_time();
  const double sps = wall > r.last_wall ? static_cast<double>(r.steps - r.last_steps) / (wall - r.last_wall) : 0.0;
  r.last_steps = r.steps;
  r.last_wall = wall;
  if (r.root) r.write_progress(metrics, allreduce_bytes, sps, wall);
  if (r.eval && r.eval->due(r.steps)) r.evaluate();
  r.decision = agree(comm, stop_signal(), r.root && r.schedule->due(r.steps));
  if (r.steps < r.total && r.decision.save_due && !r.decision.signal) save();
  return r.steps < r.total && !r.decision.signal;
}

// Both files at once: model.bin is always as recent as the checkpoint a resume would start from.
void Trainer::save() {
  if (!run_) throw Error("Trainer: save() before start()");
  Run& r = *run_;
  r.schedule->start();
  r.save_file(checkpoint_file_name, ModelKind::Checkpoint);
  r.save_file(model_file_name, ModelKind::Model);
  r.schedule->done(r.steps);
}

TrainResult Trainer::finish() {
  if (!run_) throw Error("Trainer: finish() before start()");
  Run& r = *run_;
  check_same_weights(*r.comm, *r.algo, r.state.updates);
  save();
  TrainResult result;
  result.timesteps = r.steps;
  result.total_timesteps = r.total;
  result.updates = r.state.updates;
  result.wall_time = r.vec->wall_time();
  result.stop_signal = r.decision.signal;
  result.exit_code = r.decision.signal ? 128 + r.decision.signal : 0;
  if (!r.root) {
    run_.reset();
    return result;
  }
  result.run_dir = r.start.folder->path().string();
  result.model_path = r.file(model_file_name);
  result.checkpoint_path = r.file(checkpoint_file_name);
  result.episodes = r.run_episodes->episodes(*r.vec);
  result.stats = r.run_episodes->stats(*r.vec);
  // A resumed run that was already complete: say so, not "0 steps/s" (first contact, item 8).
  const bool already_complete = r.resume && r.start_steps >= r.total && !r.decision.signal;
  if (!already_complete) r.display->show(r.steps, r.target, result.stats, r.overall_sps, result.wall_time, true);
  r.display->finish();
  if (already_complete) {
    const SettingNames& names = settings_.names;
    std::printf("rdsim train: %s is already complete (%lld of %lld steps); nothing to do. To train it further: %s (N > %lld)\n",
                result.run_dir.c_str(), r.steps, r.total,
                names.resume_call(result.run_dir, names.with(Setting::Timesteps, "N")).c_str(), r.steps);
  } else if (r.decision.signal) {
    std::fprintf(stderr, "rdsim: interrupted at %lld of %lld steps; saved %s and %s; continue with: %s\n", r.steps, r.total,
                 result.checkpoint_path.c_str(), result.model_path.c_str(), settings_.names.resume_call(result.run_dir).c_str());
  } else {
    const TrainConfig& config = r.start.config;
    std::printf("rdsim train: %s on %s, %s, %lld episodes, %s, %.1f s -> %s\n", config.algorithm.name().c_str(),
                config.env.name.c_str(), summary_steps(r.steps, r.total, r.rounding).c_str(), result.episodes,
                summary_stats(result.stats).c_str(), result.wall_time, result.model_path.c_str());
    if (r.ranks > 1) {
      const Communicator::Traffic& a = r.comm->allreduce_traffic();
      std::printf("rdsim train: %d MPI ranks x %d envs (%d threads each); rank 0 allreduced %lld bytes in %lld calls "
                  "(%.0f bytes per update) in %.2f s\n",
                  r.ranks, r.vec->size(), r.vec->num_threads(), a.bytes, a.calls,
                  r.state.updates ? static_cast<double>(a.bytes) / static_cast<double>(r.state.updates) : 0.0, a.seconds);
    }
  }
  run_.reset();  // closes the logs and releases the run folder
  return result;
}

TrainResult Trainer::run() {
  start();
  while (update()) {
  }
  return finish();
}

}  // namespace rdsim
