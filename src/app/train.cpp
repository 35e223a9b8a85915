// `rdsim train`: the one training loop for every algorithm (see include/rdsim/algorithms/algorithm.hpp).
#include "rdsim/app/train.hpp"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/app/env_source.hpp"
#include "rdsim/app/model_file.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
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

// Where a resumed run picks up the log files and the checkpoint schedule.
struct TrainerState {
  long long progress_rows = 0;
  long long episode_rows = 0;
  long long updates = 0;
};

// One line on a terminal (rewritten in place), plain periodic lines otherwise.
class ProgressDisplay {
public:
  explicit ProgressDisplay(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO) == 1) {}

  void show(long long t, long long total, const EpisodeStats& s, double sps, double wall, bool force = false) {
    if (quiet_) return;
    if (!force && wall - last_ < (tty_ ? 0.1 : 10.0)) return;
    last_ = wall;
    const double eta = sps > 0 ? static_cast<double>(total - t) / sps : 0.0;
    char ret[64] = "-";
    if (s.count > 0) std::snprintf(ret, sizeof ret, "%.1f", s.mean_return);
    std::fprintf(stderr, "%s%lld/%lld steps (%3.0f%%)  return %s  success %.2f  %.0f steps/s  ETA %.0fs%s",
                 tty_ ? "\r" : "", t, total, 100.0 * static_cast<double>(t) / static_cast<double>(total), ret,
                 s.success_rate, sps, eta < 0 ? 0.0 : eta, tty_ ? "\x1b[K" : "\n");
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (!quiet_ && tty_ && shown_) std::fputc('\n', stderr);
  }

private:
  bool quiet_, tty_;
  bool shown_ = false;
  double last_ = -1e9;
};

std::string checkpoint_payload(const Algorithm& algo, const VecEnv& vec, const TrainerState& state) {
  std::ostringstream out;
  algo.save(out, true);  // first, so `rdsim replay checkpoint.bin` reads the weights like a model's
  write_u64(out, static_cast<std::uint64_t>(state.progress_rows));
  write_u64(out, static_cast<std::uint64_t>(state.episode_rows));
  write_u64(out, static_cast<std::uint64_t>(state.updates));
  vec.save(out);
  return out.str();
}

TrainerState restore(const std::string& payload, Algorithm& algo, VecEnv& vec, const std::string& source) {
  std::istringstream in(payload);
  algo.load(in, true, source);
  TrainerState s;
  s.progress_rows = static_cast<long long>(read_u64(in, source));
  s.episode_rows = static_cast<long long>(read_u64(in, source));
  s.updates = static_cast<long long>(read_u64(in, source));
  if (!vec.load(in, source)) {
    std::fprintf(stderr, "rdsim: note: these envs cannot save their state; the resumed run starts fresh "
                         "episodes and will not match an uninterrupted run exactly\n");
  }
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": file is damaged (unexpected trailing data)");
  return s;
}

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
  CsvWriter log((dir / "pretrain.csv").string(), columns);
  for (const Metrics& row : rows) {
    std::vector<std::string> cells;
    for (const auto& [name, value] : row) cells.push_back(CsvWriter::cell(value));
    log.write_row(cells);
  }
  if (!quiet) {
    long long steps = 0;
    for (const DemoEpisode& e : demos.episodes) steps += e.steps();
    std::fprintf(stderr, "rdsim train: learnt from %zu demonstrated episodes (%lld steps) of %s: %zu epochs -> %s\n",
                 demos.episodes.size(), steps, dc.file.c_str(), rows.size(), (dir / "pretrain.csv").string().c_str());
  }
}

std::vector<std::string> episode_row(const EpisodeRecord& e) {
  return {CsvWriter::cell(e.episode), CsvWriter::cell(e.timesteps), CsvWriter::cell(e.episode_return),
          CsvWriter::cell(e.length),  CsvWriter::cell(e.success),   CsvWriter::cell(e.collision),
          CsvWriter::cell(e.out_of_bounds), CsvWriter::cell(e.wall_time)};
}

}  // namespace

int train_command(const TrainOptions& o) {
  const bool resume = !o.resume_dir.empty();
  TrainConfig config;
  ModelFile checkpoint;
  std::string checkpoint_path;
  if (resume) {
    if (o.seed) throw Error("train: --seed cannot change a resumed run (it continues the checkpoint's seed)");
    if (!o.log_dir.empty()) throw Error("train: --log-dir cannot be combined with --resume (the run folder is DIR)");
    checkpoint_path = (std::filesystem::path(o.resume_dir) / "checkpoint.bin").string();
    checkpoint = read_model_file(checkpoint_path);
    if (checkpoint.kind != ModelKind::Checkpoint) throw Error(checkpoint_path + ": is a model, not a checkpoint");
    config = parse_train_config(checkpoint.config, checkpoint_path + " (embedded config)", "resumed");
    config.log_dir = o.resume_dir;
  } else {
    config = read_train_config(o.config_path);
    if (o.seed) config.seed = *o.seed;
    if (!o.log_dir.empty()) config.log_dir = o.log_dir;
  }
  if (o.timesteps) config.total_timesteps = *o.timesteps;

  const std::filesystem::path dir(config.log_dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(config.log_dir + ": cannot create the run folder: " + ec.message());

  VecEnv vec(open_envs(config), config.seed, config.stats_window);
  auto algo = make_algorithm(config.algorithm, config.seed, vec.spec());
  TrainerState state;
  if (resume) state = restore(checkpoint.payload, *algo, vec, checkpoint_path);
  if (config.algorithm.demonstrations) learn_from_demonstrations(config, *algo, vec.spec(), resume, dir, o.quiet);

  const nlohmann::json resolved = to_json(config);
  write_file_atomic((dir / "config.json").string(), resolved.dump(2) + "\n");
  CsvWriter episodes((dir / "episodes.csv").string(), episode_columns, resume ? state.episode_rows : -1);
  std::unique_ptr<CsvWriter> progress;  // its columns are known after the first update

  auto save = [&](const std::string& file, ModelKind kind) {
    ModelFile f;
    f.kind = kind;
    f.config = resolved;
    if (kind == ModelKind::Model) {
      std::ostringstream out;
      algo->save(out, false);
      f.payload = out.str();
    } else {
      state.progress_rows = progress ? progress->rows() : state.progress_rows;
      state.episode_rows = episodes.rows();
      f.payload = checkpoint_payload(*algo, vec, state);
    }
    write_model_file((dir / file).string(), f);
  };

  const long long total = config.total_timesteps;
  const long long interval = config.checkpoint_interval;
  long long next_checkpoint = interval > 0 ? (vec.timesteps() / interval + 1) * interval : 0;
  ProgressDisplay display(o.quiet);
  const long long start_steps = vec.timesteps();
  const double start_wall = vec.wall_time();
  long long last_steps = start_steps;
  double last_wall = start_wall;
  double overall_sps = 0.0;

  while (vec.timesteps() < total) {
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
      progress = std::make_unique<CsvWriter>((dir / "progress.csv").string(), columns, resume ? state.progress_rows : -1);
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
    if (interval > 0 && vec.timesteps() >= next_checkpoint) {
      save("checkpoint.bin", ModelKind::Checkpoint);
      next_checkpoint = (vec.timesteps() / interval + 1) * interval;
    }
  }
  save("model.bin", ModelKind::Model);
  save("checkpoint.bin", ModelKind::Checkpoint);

  const EpisodeStats s = vec.episodes().stats();
  display.show(vec.timesteps(), total, s, overall_sps, vec.wall_time(), true);
  display.finish();
  if (!o.quiet) {
    std::printf("rdsim train: %s on %s, %lld timesteps, %lld episodes, mean return of the last %d: %.2f, "
                "%.1f s -> %s\n",
                config.algorithm.name().c_str(), config.env.name.c_str(), vec.timesteps(), vec.episodes().episodes(),
                s.count, s.mean_return, vec.wall_time(), (dir / "model.bin").string().c_str());
  }
  return 0;
}

}  // namespace rdsim
