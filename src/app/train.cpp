// `rdsim train`: the one training loop for every algorithm (see include/rdsim/algorithms/algorithm.hpp).
#include "rdsim/app/train.hpp"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/app/data_parallel.hpp"
#include "rdsim/app/model_file.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
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

std::vector<std::unique_ptr<Env>> make_envs(const TrainConfig& config) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < config.num_envs; ++i) envs.push_back(make_env(config.env));
  return envs;
}

std::string checkpoint_payload(const Algorithm& algo, const VecEnv& vec, const TrainerState& state) {
  std::ostringstream out;
  algo.save(out, true);  // first, so `rdsim replay checkpoint.bin` reads the weights like a model's
  write_u64(out, static_cast<std::uint64_t>(state.progress_rows));
  write_u64(out, static_cast<std::uint64_t>(state.episode_rows));
  write_u64(out, static_cast<std::uint64_t>(state.updates));
  vec.save(out);
  return out.str();
}

TrainerState restore(const std::string& payload, Algorithm& algo, VecEnv& vec, const std::string& source, bool root) {
  std::istringstream in(payload);
  algo.load(in, true, source);
  TrainerState s;
  s.progress_rows = static_cast<long long>(read_u64(in, source));
  s.episode_rows = static_cast<long long>(read_u64(in, source));
  s.updates = static_cast<long long>(read_u64(in, source));
  if (!vec.load(in, source) && root) {
    std::fprintf(stderr, "rdsim: note: these envs cannot save their state; the resumed run starts fresh "
                         "episodes and will not match an uninterrupted run exactly\n");
  }
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": file is damaged (unexpected trailing data)");
  return s;
}

std::vector<std::string> episode_row(const EpisodeRecord& e) {
  return {CsvWriter::cell(e.episode), CsvWriter::cell(e.timesteps), CsvWriter::cell(e.episode_return),
          CsvWriter::cell(e.length),  CsvWriter::cell(e.success),   CsvWriter::cell(e.collision),
          CsvWriter::cell(e.out_of_bounds), CsvWriter::cell(e.wall_time)};
}

// The run's config: read (or taken from the checkpoint) on rank 0 and sent to the other ranks, so
// that only rank 0 needs the files. Fills `checkpoint` when resuming.
TrainConfig load_config(const TrainOptions& o, Communicator& comm, ModelFile& checkpoint, std::string& checkpoint_path) {
  const bool resume = !o.resume_dir.empty();
  TrainConfig config;
  if (resume) {
    if (o.seed) throw Error("train: --seed cannot change a resumed run (it continues the checkpoint's seed)");
    if (!o.log_dir.empty()) throw Error("train: --log-dir cannot be combined with --resume (the run folder is DIR)");
    checkpoint_path = (std::filesystem::path(o.resume_dir) / "checkpoint.bin").string();
    std::string bytes = comm.rank() == 0 ? read_file(checkpoint_path) : std::string();
    comm.broadcast(bytes, 0);
    checkpoint = decode_model_file(bytes, checkpoint_path);
    if (checkpoint.kind != ModelKind::Checkpoint) throw Error(checkpoint_path + ": is a model, not a checkpoint");
    config = parse_train_config(checkpoint.config, checkpoint_path + " (embedded config)", "resumed");
    config.log_dir = o.resume_dir;
  } else {
    std::string text;
    if (comm.rank() == 0) {
      config = read_train_config(o.config_path);
      text = to_json(config).dump();
    }
    comm.broadcast(text, 0);
    if (comm.rank() != 0) {
      const std::string name = std::filesystem::path(o.config_path).stem().string();
      config = parse_train_config(nlohmann::json::parse(text), o.config_path + " (from rank 0)", name);
    }
    if (o.seed) config.seed = *o.seed;
    if (!o.log_dir.empty()) config.log_dir = o.log_dir;
  }
  if (o.timesteps) config.total_timesteps = *o.timesteps;
  if (o.threads) config.num_threads = *o.threads;
  return config;
}

}  // namespace

int train_command(const TrainOptions& o) {
  Communicator& comm = o.communicator ? *o.communicator : single_process_communicator();
  const bool root = comm.rank() == 0;  // rank 0 writes the run folder
  const int ranks = comm.size();
  const bool resume = !o.resume_dir.empty();
  ModelFile checkpoint;
  std::string checkpoint_path;
  TrainConfig config = load_config(o, comm, checkpoint, checkpoint_path);

  const std::filesystem::path dir(config.log_dir);
  if (root) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error(config.log_dir + ": cannot create the run folder: " + ec.message());
  }

  const std::uint64_t seed = rank_seed(config.seed, comm.rank());
  VecEnv vec(make_envs(config), seed, config.stats_window, resolve_num_threads(config, comm.local_size()));
  auto algo = make_algorithm(config.algorithm, seed, vec.spec());
  algo->set_communicator(comm);
  RunEpisodes run_episodes(comm, config.stats_window);
  TrainerState state;
  if (resume) {
    state = restore(checkpoint_part(comm, checkpoint.payload, run_episodes, checkpoint_path), *algo, vec,
                    checkpoint_path, root);
  } else {
    share_weights(comm, *algo);
  }

  const nlohmann::json resolved = to_json(config);
  std::unique_ptr<CsvWriter> episodes, progress;  // rank 0; progress's columns are known after the first update
  if (root) {
    write_file_atomic((dir / "config.json").string(), resolved.dump(2) + "\n");
    episodes = std::make_unique<CsvWriter>((dir / "episodes.csv").string(), episode_columns, resume ? state.episode_rows : -1);
  }

  // Collective under MPI: every rank calls it, rank 0 writes the file.
  auto save = [&](const std::string& file, ModelKind kind) {
    ModelFile f;
    f.kind = kind;
    f.config = resolved;
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
    write_model_file((dir / file).string(), f);
  };

  // total_timesteps counts the steps of all ranks; the ranks step in lockstep, each its share.
  const long long total = config.total_timesteps;
  const long long rank_total = (total + ranks - 1) / ranks;
  const long long interval = config.checkpoint_interval;
  auto run_timesteps = [&] { return vec.timesteps() * ranks; };
  long long next_checkpoint = interval > 0 ? (run_timesteps() / interval + 1) * interval : 0;
  ProgressDisplay display(o.quiet || !root);
  const long long start_steps = run_timesteps();
  const double start_wall = vec.wall_time();
  long long last_steps = start_steps;
  double last_wall = start_wall;
  double overall_sps = 0.0;
  long long last_allreduce_bytes = comm.allreduce_traffic().bytes;

  while (vec.timesteps() < rank_total) {
    const Metrics metrics = algo->update(vec, {vec.timesteps(), rank_total});
    ++state.updates;
    for (const auto& e : run_episodes.take_finished(vec)) episodes->write_row(episode_row(e));
    if (config.sync_check_interval > 0 && state.updates % config.sync_check_interval == 0)
      check_same_weights(comm, *algo, state.updates);
    const long long allreduce_bytes = comm.allreduce_traffic().bytes - last_allreduce_bytes;
    last_allreduce_bytes = comm.allreduce_traffic().bytes;

    const double wall = vec.wall_time();
    const long long t = run_timesteps();
    const double sps = wall > last_wall ? static_cast<double>(t - last_steps) / (wall - last_wall) : 0.0;
    last_steps = t;
    last_wall = wall;
    if (root) {
      if (!progress) {
        std::vector<std::string> columns = progress_head;
        for (const auto& [name, value] : metrics) columns.push_back(name);
        if (ranks > 1) columns.push_back("allreduce_bytes");
        columns.insert(columns.end(), progress_tail.begin(), progress_tail.end());
        progress = std::make_unique<CsvWriter>((dir / "progress.csv").string(), columns, resume ? state.progress_rows : -1);
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
    if (interval > 0 && t >= next_checkpoint) {
      save("checkpoint.bin", ModelKind::Checkpoint);
      next_checkpoint = (t / interval + 1) * interval;
    }
  }
  check_same_weights(comm, *algo, state.updates);
  save("model.bin", ModelKind::Model);
  save("checkpoint.bin", ModelKind::Checkpoint);
  if (!root) return 0;

  const EpisodeStats s = run_episodes.stats(vec);
  display.show(run_timesteps(), total, s, overall_sps, vec.wall_time(), true);
  display.finish();
  if (!o.quiet) {
    std::printf("rdsim train: %s on %s, %lld timesteps, %lld episodes, mean return of the last %d: %.2f, "
                "%.1f s -> %s\n",
                config.algorithm.name().c_str(), config.env.name.c_str(), run_timesteps(), run_episodes.episodes(vec),
                s.count, s.mean_return, vec.wall_time(), (dir / "model.bin").string().c_str());
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
