// `rdsim train`: the one training loop for every algorithm (see include/rdsim/algorithms/algorithm.hpp).
#include "rdsim/app/train.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/app/checkpoint.hpp"
#include "rdsim/app/data_parallel.hpp"
#include "rdsim/app/dashboard.hpp"
#include "rdsim/app/env_source.hpp"
#include "rdsim/app/interrupt.hpp"
#include "rdsim/app/memory_check.hpp"
#include "rdsim/app/model_file.hpp"
#include "rdsim/app/progress_display.hpp"
#include "rdsim/app/run_folder.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/dashboard/dashboard_server.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_fit.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {
namespace {

const std::vector<std::string> episode_columns = {"episode", "timesteps", "return", "length", "success", "collision", "out_of_bounds", "wall_time"};
const std::vector<std::string> progress_head = {"timesteps", "updates", "episodes", "mean_return", "min_return",
                                                "max_return", "mean_length", "success_rate"};
// Last, so that comparing two runs can simply drop them: they are the only non-reproducible columns.
const std::vector<std::string> progress_tail = {"steps_per_s", "wall_time"};

// The config's "demonstrations": the file read and checked against the env, then handed to the
// algorithm (pre-training on a fresh run; pretrain.csv gets one row per epoch).
void learn_from_demonstrations(const TrainConfig& config, Algorithm& algo, const Spec& spec, bool resume,
                               const std::filesystem::path& dir, bool quiet) {
  const DemonstrationsConfig& dc = *config.algorithm.demonstrations;
  const DemoFile demos = read_demo_file(dc.file);
  check_demos_fit(demos, to_json(config.env), spec);
  if (demos.episodes.empty()) throw Error(dc.file + ": holds no episode to learn from");
  Rng rng = Rng::derive(config.seed, rng_stream::demonstrations);
  const std::vector<Metrics> rows = algo.learn_from_demonstrations(demos, dc, rng, !resume);
  if (rows.empty() || dir.empty()) return;  // dir: empty on MPI ranks other than 0
  std::vector<std::string> columns;
  for (const auto& [name, value] : rows.front()) columns.push_back(name);
  CsvWriter log((dir / pretrain_csv_name).string(), columns);
  for (const Metrics& row : rows) {
    std::vector<std::string> cells;
    for (const auto& [name, value] : row) cells.push_back(CsvWriter::cell(value));
    log.write_row(cells);
  }
  if (!quiet) {
    long long steps = 0;
    for (const DemoEpisode& e : demos.episodes) steps += e.steps();
    std::fprintf(stderr, "rdsim train: learnt from %zu demonstrated episodes (%lld steps) of %s: %zu epochs -> %s\n",
                 demos.episodes.size(), steps, dc.file.c_str(), rows.size(), (dir / pretrain_csv_name).string().c_str());
  }
}

std::vector<std::string> episode_row(const EpisodeRecord& e) {
  return {CsvWriter::cell(e.episode), CsvWriter::cell(e.timesteps), CsvWriter::cell(e.episode_return),
          CsvWriter::cell(e.length),  CsvWriter::cell(e.success),   CsvWriter::cell(e.collision),
          CsvWriter::cell(e.out_of_bounds), CsvWriter::cell(e.wall_time)};
}

// The run's config and folder. A new run reads its config file (with the command line's
// overrides) and takes a folder that holds no other run; a resumed one takes its folder first,
// then reads the config its checkpoint embeds. Either way the memory the config implies is
// checked before anything large exists. Under MPI rank 0 alone reads the files and holds the
// folder (and its lock); the other ranks get the config and the checkpoint from it.
struct RunStart {
  TrainConfig config;
  std::unique_ptr<RunFolder> folder;  // rank 0
  ModelFile checkpoint;               // resume only
  std::string checkpoint_path;        // resume only
};

RunStart start_run(const TrainOptions& o, Communicator& comm) {
  RunStart run;
  const bool root = comm.rank() == 0;
  const MemoryLimit limit = memory_limit(o.max_memory_gb);
  // Errors: each step runs on_every_rank, so a bad config is reported once (by rank 0) and every
  // rank leaves with its exit code, none left waiting in a broadcast.
  if (o.resume_dir.empty()) {
    std::string text;
    on_every_rank(comm, [&] {
      if (!root) return;
      run.config = read_train_config(o.config_path, o.overrides);
      if (o.threads) run.config.num_threads = *o.threads;
      check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, run.config.source);
      run.folder = std::make_unique<RunFolder>(run.config.log_dir, o.overwrite ? RunFolder::Mode::Overwrite : RunFolder::Mode::New);
      text = to_json(run.config).dump();
    });
    if (comm.size() > 1) {
      comm.broadcast(text, 0);
      on_every_rank(comm, [&] {
        if (root) return;
        const std::string name = std::filesystem::path(o.config_path).stem().string();
        run.config = parse_train_config(nlohmann::json::parse(text), o.config_path + " (from rank 0)", name);
        if (o.threads) run.config.num_threads = *o.threads;
        check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, o.config_path);
      });
    }
    return run;
  }
  run.checkpoint_path = (std::filesystem::path(o.resume_dir) / checkpoint_file_name).string();
  on_every_rank(comm, [&] {
    for (const ConfigOverride& v : o.overrides) {
      if (v.key == "seed") throw Error("train: --seed cannot change a resumed run (it continues the checkpoint's seed)");
      if (v.key == "log_dir") throw Error("train: --log-dir cannot be combined with --resume (the run folder is DIR)");
    }
    if (o.overwrite) throw Error("train: --overwrite cannot be combined with --resume");
    if (!root) return;
    run.folder = std::make_unique<RunFolder>(o.resume_dir, RunFolder::Mode::Resume);
    run.checkpoint = read_model_file(run.checkpoint_path);
  });
  if (comm.size() > 1) {  // every rank needs the whole file: it holds every rank's state
    std::string bytes = root ? encode_model_file(run.checkpoint) : std::string();
    comm.broadcast(bytes, 0);
    on_every_rank(comm, [&] {
      if (!root) run.checkpoint = decode_model_file(bytes, run.checkpoint_path);
    });
  }
  on_every_rank(comm, [&] {
    const std::string& path = run.checkpoint_path;
    if (run.checkpoint.kind != ModelKind::Checkpoint) throw Error(path + ": is a model, not a checkpoint");
    nlohmann::json embedded = run.checkpoint.config;
    apply_overrides(embedded, o.overrides, path + " (embedded config)");
    run.config = parse_train_config(embedded, path + " (embedded config)", "resumed");
    run.config.log_dir = o.resume_dir;
    if (o.threads) run.config.num_threads = *o.threads;
    check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, path);
  });
  return run;
}

// What the ranks agree on after each update, so that they leave the loop and save together:
// the largest interrupt signal any rank received (0: none) and whether rank 0's checkpoint
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

}  // namespace

int train_command(const TrainOptions& o) {
  InterruptGuard interrupts;  // before anything slow: a Ctrl-C during setup still saves or quits cleanly
  Communicator& comm = o.communicator ? *o.communicator : single_process_communicator();
  const bool root = comm.rank() == 0;  // rank 0 holds and writes the run folder
  const int ranks = comm.size();
  RunStart run = start_run(o, comm);
  TrainConfig& config = run.config;  // open_envs records a remote env's resolved values in it
  const bool resume = !o.resume_dir.empty();
  const std::string& checkpoint_path = run.checkpoint_path;
  auto file = [&](const std::string& name) { return run.folder->file(name); };  // rank 0

  const std::uint64_t seed = rank_seed(config.seed, comm.rank());
  std::unique_ptr<VecEnv> vec_owner;
  std::unique_ptr<Algorithm> algo;
  on_every_rank(comm, [&] {  // an env or algorithm that refuses the config: one message
    vec_owner = std::make_unique<VecEnv>(open_envs(config), seed, config.stats_window,
                                         resolve_num_threads(config, comm.local_size()), resolve_env_workers(config));
    algo = make_algorithm(config.algorithm, seed, vec_owner->spec());
  });
  VecEnv& vec = *vec_owner;
  algo->set_communicator(comm);
  check_data_parallel(comm, *algo);
  RunEpisodes run_episodes(comm, config.stats_window, algo->lockstep());
  TrainerState state;
  if (resume) {
    check_model_spec(run.checkpoint, vec.spec(), checkpoint_path);
    state = restore_checkpoint(checkpoint_part(comm, run.checkpoint.payload, run_episodes, checkpoint_path), *algo, vec,
                               checkpoint_path, root);
    run.checkpoint.payload.clear();
    if (root) {
      check_log_rows(file(progress_csv_name), state.progress_rows, checkpoint_path);
      check_log_rows(file(episodes_csv_name), state.episode_rows, checkpoint_path);
    }
  }
  // Under MPI every rank learns from the demonstrations (the same draws: the stream is the run's,
  // not the rank's) and rank 0 writes pretrain.csv.
  if (config.algorithm.demonstrations)
    learn_from_demonstrations(config, *algo, vec.spec(), resume, root ? run.folder->path() : std::filesystem::path(),
                              o.quiet || !root);
  if (!resume) share_weights(comm, *algo);

  const nlohmann::json resolved = to_json(config);
  std::unique_ptr<DashboardServer> dashboard;  // rank 0, with --dashboard
  std::unique_ptr<CsvWriter> episodes, progress;  // rank 0; progress's columns are known after the first update
  if (root) {
    write_file_atomic(file(run_config_name), resolved.dump(2) + "\n");
    // reads the run's files only
    dashboard = start_run_dashboard(o.dashboard, run.folder->path().string(), o.quiet);
    episodes = std::make_unique<CsvWriter>(file(episodes_csv_name), episode_columns, resume ? state.episode_rows : -1);
  }

  // Collective under MPI: every rank calls it, rank 0 writes the file.
  auto save_file = [&](const std::string& name, ModelKind kind) {
    ModelFile f;
    f.kind = kind;
    f.config = resolved;
    f.spec = describe_spec(vec.spec());
    if (kind == ModelKind::Model) {
      if (!root) return;
      std::ostringstream out;
      algo->save(out, false);
      f.payload = out.str();
    } else {
      if (root) {
        state.progress_rows = progress ? progress->rows() : state.progress_rows;
        state.episode_rows = episodes->rows();
      }
      f.payload = gather_checkpoint(comm, checkpoint_payload(*algo, vec, state), run_episodes);
      if (!root) return;
    }
    write_model_file(file(name), f);
  };
  // total_timesteps counts the steps of all ranks (the gradient methods' ranks step in lockstep,
  // each its share; the population methods' do not). `steps`: the run's, the same on every rank.
  const long long total = config.total_timesteps;
  const long long rank_total = (total + ranks - 1) / ranks;
  long long steps = run_timesteps(comm, vec);
  CheckpointSchedule schedule(config.checkpoint_interval, config.checkpoint_seconds, steps);
  // Both files at once: model.bin is always as recent as the checkpoint a resume would start from.
  auto save = [&] {
    schedule.start();
    save_file(checkpoint_file_name, ModelKind::Checkpoint);
    save_file(model_file_name, ModelKind::Model);
    schedule.done(steps);
  };
  if (!resume) save();  // from the start, `--resume` always finds something to continue

  ProgressDisplay display(o.quiet || !root);
  const long long start_steps = steps;
  const double start_wall = vec.wall_time();
  long long last_steps = start_steps;
  double last_wall = start_wall;
  double overall_sps = 0.0;
  long long last_allreduce_bytes = comm.allreduce_traffic().bytes;

  LoopDecision decision = agree(comm, interrupts.requested(), false);
  while (steps < total && !decision.signal) {
    vec.drop_caches();  // every update starts from what a checkpoint restores (core/env_state.hpp)
    const Metrics metrics = algo->update(vec, {vec.timesteps(), rank_total});
    const long long steps_before = steps;
    steps = run_timesteps(comm, vec);
    ++state.updates;
    for (const auto& e : run_episodes.take_finished(vec, steps_before)) episodes->write_row(episode_row(e));
    if (config.sync_check_interval > 0 && state.updates % config.sync_check_interval == 0)
      check_same_weights(comm, *algo, state.updates);
    const long long allreduce_bytes = comm.allreduce_traffic().bytes - last_allreduce_bytes;
    last_allreduce_bytes = comm.allreduce_traffic().bytes;

    const double wall = vec.wall_time();
    const long long t = steps;
    const double sps = wall > last_wall ? static_cast<double>(t - last_steps) / (wall - last_wall) : 0.0;
    last_steps = t;
    last_wall = wall;
    if (root) {
      if (!progress) {
        std::vector<std::string> columns = progress_head;
        for (const auto& [name, value] : metrics) columns.push_back(name);
        if (ranks > 1) columns.push_back("allreduce_bytes");
        columns.insert(columns.end(), progress_tail.begin(), progress_tail.end());
        progress = std::make_unique<CsvWriter>(file(progress_csv_name), columns, resume ? state.progress_rows : -1);
      }
      const EpisodeStats s = run_episodes.stats(vec);
      const double nan = std::numeric_limits<double>::quiet_NaN();
      std::vector<std::string> row = {CsvWriter::cell(t),
                                      CsvWriter::cell(state.updates),
                                      CsvWriter::cell(run_episodes.episodes(vec)),
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
      overall_sps = wall > start_wall ? static_cast<double>(t - start_steps) / (wall - start_wall) : 0.0;
      display.show(t, total, s, overall_sps, wall);
    }
    decision = agree(comm, interrupts.requested(), root && schedule.due(t));
    if (steps < total && decision.save_due && !decision.signal) save();
  }
  check_same_weights(comm, *algo, state.updates);
  save();
  if (!root) return decision.signal ? 128 + decision.signal : 0;

  const EpisodeStats s = run_episodes.stats(vec);
  display.show(steps, total, s, overall_sps, vec.wall_time(), true);
  display.finish();
  if (decision.signal) {
    std::fprintf(stderr, "rdsim: interrupted at %lld of %lld steps; saved %s and %s; continue with: rdsim train --resume %s\n",
                 steps, total, file(checkpoint_file_name).c_str(),
                 file(model_file_name).c_str(), run.folder->path().string().c_str());
    return 128 + decision.signal;
  }
  if (!o.quiet) {
    std::printf("rdsim train: %s on %s, %lld timesteps, %lld episodes, mean return of the last %d: %.2f, "
                "%.1f s -> %s\n",
                config.algorithm.name().c_str(), config.env.name.c_str(), steps, run_episodes.episodes(vec),
                s.count, s.mean_return, vec.wall_time(), file(model_file_name).c_str());
    if (ranks > 1) {
      const Communicator::Traffic& a = comm.allreduce_traffic();
      std::printf("rdsim train: %d MPI ranks x %d envs (%d threads each); rank 0 allreduced %lld bytes in %lld calls "
                  "(%.0f bytes per update) in %.2f s\n",
                  ranks, vec.size(), vec.num_threads(), a.bytes, a.calls,
                  state.updates ? static_cast<double>(a.bytes) / static_cast<double>(state.updates) : 0.0, a.seconds);
    }
  }
  return 0;
}

}  // namespace rdsim
