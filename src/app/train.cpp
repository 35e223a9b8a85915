// `rdsim train`: the one training loop for every algorithm (see include/rdsim/algorithms/algorithm.hpp).
#include "rdsim/app/train.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/app/checkpoint.hpp"
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
  if (rows.empty()) return;
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

// The run's config and folder: a new run reads its config file (with the command line's
// overrides) and takes a folder that holds no other run; a resumed one takes its folder first,
// then reads the config its checkpoint embeds. Either way the memory the config implies is
// checked before anything large exists.
struct RunStart {
  TrainConfig config;
  std::unique_ptr<RunFolder> folder;
  ModelFile checkpoint;  // resume only
};

RunStart start_run(const TrainOptions& o) {
  RunStart run;
  const MemoryLimit limit = memory_limit(o.max_memory_gb);
  if (o.resume_dir.empty()) {
    run.config = read_train_config(o.config_path, o.overrides);
    check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, run.config.source);
    run.folder = std::make_unique<RunFolder>(run.config.log_dir, o.overwrite ? RunFolder::Mode::Overwrite : RunFolder::Mode::New);
    return run;
  }
  for (const ConfigOverride& v : o.overrides) {
    if (v.key == "seed") throw Error("train: --seed cannot change a resumed run (it continues the checkpoint's seed)");
    if (v.key == "log_dir") throw Error("train: --log-dir cannot be combined with --resume (the run folder is DIR)");
  }
  if (o.overwrite) throw Error("train: --overwrite cannot be combined with --resume");
  run.folder = std::make_unique<RunFolder>(o.resume_dir, RunFolder::Mode::Resume);
  const std::string path = run.folder->file(checkpoint_file_name);
  run.checkpoint = read_model_file(path);
  if (run.checkpoint.kind != ModelKind::Checkpoint) throw Error(path + ": is a model, not a checkpoint");
  nlohmann::json embedded = run.checkpoint.config;
  apply_overrides(embedded, o.overrides, path + " (embedded config)");
  run.config = parse_train_config(embedded, path + " (embedded config)", "resumed");
  run.config.log_dir = o.resume_dir;
  check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, path);
  return run;
}

}  // namespace

int train_command(const TrainOptions& o) {
  InterruptGuard interrupts;  // before anything slow: a Ctrl-C during setup still saves or quits cleanly
  RunStart run = start_run(o);
  TrainConfig& config = run.config;  // open_envs records a remote env's resolved values in it
  const RunFolder& folder = *run.folder;
  const bool resume = !o.resume_dir.empty();
  const std::string checkpoint_path = folder.file(checkpoint_file_name);

  VecEnv vec(open_envs(config), config.seed, config.stats_window);
  auto algo = make_algorithm(config.algorithm, config.seed, vec.spec());
  TrainerState state;
  if (resume) {
    check_model_spec(run.checkpoint, vec.spec(), checkpoint_path);
    state = restore_checkpoint(run.checkpoint.payload, *algo, vec, checkpoint_path);
    run.checkpoint.payload.clear();
    check_log_rows(folder.file(progress_csv_name), state.progress_rows, checkpoint_path);
    check_log_rows(folder.file(episodes_csv_name), state.episode_rows, checkpoint_path);
  }
  if (config.algorithm.demonstrations) learn_from_demonstrations(config, *algo, vec.spec(), resume, folder.path(), o.quiet);

  const nlohmann::json resolved = to_json(config);
  write_file_atomic(folder.file(run_config_name), resolved.dump(2) + "\n");
  const auto dashboard = start_run_dashboard(o.dashboard, folder.path().string(), o.quiet);  // reads the run's files only
  CsvWriter episodes(folder.file(episodes_csv_name), episode_columns, resume ? state.episode_rows : -1);
  std::unique_ptr<CsvWriter> progress;  // its columns are known after the first update

  auto save_file = [&](const std::string& file, ModelKind kind) {
    ModelFile f;
    f.kind = kind;
    f.config = resolved;
    f.spec = describe_spec(vec.spec());
    if (kind == ModelKind::Model) {
      std::ostringstream out;
      algo->save(out, false);
      f.payload = out.str();
    } else {
      state.progress_rows = progress ? progress->rows() : state.progress_rows;
      state.episode_rows = episodes.rows();
      f.payload = checkpoint_payload(*algo, vec, state);
    }
    write_model_file(folder.file(file), f);
  };
  CheckpointSchedule schedule(config.checkpoint_interval, config.checkpoint_seconds, vec.timesteps());
  // Both files at once: model.bin is always as recent as the checkpoint a resume would start from.
  auto save = [&] {
    schedule.start();
    save_file(checkpoint_file_name, ModelKind::Checkpoint);
    save_file(model_file_name, ModelKind::Model);
    schedule.done(vec.timesteps());
  };
  if (!resume) save();  // from the start, `--resume` always finds something to continue

  const long long total = config.total_timesteps;
  ProgressDisplay display(o.quiet);
  const long long start_steps = vec.timesteps();
  const double start_wall = vec.wall_time();
  long long last_steps = start_steps;
  double last_wall = start_wall;
  double overall_sps = 0.0;

  while (vec.timesteps() < total && !interrupts.requested()) {
    vec.drop_caches();  // every update starts from what a checkpoint restores (core/env_state.hpp)
    const Metrics metrics = algo->update(vec, {vec.timesteps(), total});
    ++state.updates;
    for (const auto& e : vec.episodes().take_finished()) episodes.write_row(episode_row(e));

    const double wall = vec.wall_time();
    const double sps = wall > last_wall ? static_cast<double>(vec.timesteps() - last_steps) / (wall - last_wall) : 0.0;
    last_steps = vec.timesteps();
    last_wall = wall;
    if (!progress) {
      std::vector<std::string> columns = progress_head;
      for (const auto& [name, value] : metrics) columns.push_back(name);
      columns.insert(columns.end(), progress_tail.begin(), progress_tail.end());
      progress = std::make_unique<CsvWriter>(folder.file(progress_csv_name), columns, resume ? state.progress_rows : -1);
    }
    const EpisodeStats s = vec.episodes().stats();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::string> row = {CsvWriter::cell(vec.timesteps()),
                                    CsvWriter::cell(state.updates),
                                    CsvWriter::cell(vec.episodes().episodes()),
                                    CsvWriter::cell(s.count ? s.mean_return : nan),
                                    CsvWriter::cell(s.count ? s.min_return : nan),
                                    CsvWriter::cell(s.count ? s.max_return : nan),
                                    CsvWriter::cell(s.count ? s.mean_length : nan),
                                    CsvWriter::cell(s.count ? s.success_rate : nan)};
    for (const auto& [name, value] : metrics) row.push_back(CsvWriter::cell(value));
    row.push_back(CsvWriter::cell(sps));
    row.push_back(CsvWriter::cell(wall));
    progress->write_row(row);

    overall_sps = wall > start_wall ? static_cast<double>(vec.timesteps() - start_steps) / (wall - start_wall) : 0.0;
    display.show(vec.timesteps(), total, s, overall_sps, wall);
    if (vec.timesteps() < total && schedule.due(vec.timesteps()) && !interrupts.requested()) save();
  }
  save();

  const EpisodeStats s = vec.episodes().stats();
  display.show(vec.timesteps(), total, s, overall_sps, vec.wall_time(), true);
  display.finish();
  if (interrupts.requested()) {
    std::fprintf(stderr, "rdsim: interrupted at %lld of %lld steps; saved %s and %s; continue with: rdsim train --resume %s\n",
                 vec.timesteps(), total, checkpoint_path.c_str(), folder.file(model_file_name).c_str(),
                 folder.path().string().c_str());
    return interrupts.exit_code();
  }
  if (!o.quiet) {
    std::printf("rdsim train: %s on %s, %lld timesteps, %lld episodes, mean return of the last %d: %.2f, "
                "%.1f s -> %s\n",
                config.algorithm.name().c_str(), config.env.name.c_str(), vec.timesteps(), vec.episodes().episodes(),
                s.count, s.mean_return, vec.wall_time(), folder.file(model_file_name).c_str());
  }
  return 0;
}

}  // namespace rdsim
