#include "run_start.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/training/data_parallel.hpp"
#include "rdsim/training/memory_check.hpp"

namespace rdsim {
namespace {

// Where a config given as JSON comes from, in messages.
constexpr const char* kJsonSource = "config";

std::string config_source(const TrainerSettings& o) { return o.config_path.empty() ? kJsonSource : o.config_path; }

// A config given as JSON without a log_dir has no file name to name its folder after: it trains
// into runs/ENV_ALGORITHM_K, the first K whose folder holds no run yet (as SB3 numbers its logs),
// so a second run never collides with the first.
std::string free_run_folder(const TrainConfig& c) {
  namespace fs = std::filesystem;
  const std::string stem = "runs/" + c.env.name + "_" + c.algorithm.name() + "_";
  for (int k = 1;; ++k) {
    const fs::path dir = stem + std::to_string(k);
    std::error_code ec;
    bool used = false;
    for (const std::string& f : RunFolder::run_files()) used = used || fs::exists(dir / f, ec);
    if (!used) return dir.string();
  }
}

TrainConfig read_config(const TrainerSettings& o) {
  if (!o.config_path.empty()) return read_train_config(o.config_path, o.overrides);
  nlohmann::json json = o.config;
  apply_overrides(json, o.overrides, kJsonSource);
  TrainConfig c = parse_train_config(json, kJsonSource, "");
  if (c.log_dir.empty()) c.log_dir = free_run_folder(c);
  if (c.name.empty()) c.name = std::filesystem::path(c.log_dir).filename().string();
  return c;
}

void check_settings(const TrainerSettings& o) {
  if (!o.resume_dir.empty() && (!o.config_path.empty() || !o.config.is_null()))
    throw Error("train: a resumed run takes its config from its checkpoint: give a config or a run folder to resume, not both");
  if (o.resume_dir.empty() && o.config_path.empty() && o.config.is_null())
    throw Error("train: give a config (a file or JSON) or a run folder to resume");
}

void start_new_run(RunStart& run, const TrainerSettings& o, Communicator& comm, const MemoryLimit& limit) {
  const bool root = comm.rank() == 0;
  std::string text;
  on_every_rank(comm, [&] {
    if (!root) return;
    run.config = read_config(o);
    if (o.threads) run.config.num_threads = *o.threads;
    check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, run.config.source);
    run.folder = std::make_unique<RunFolder>(run.config.log_dir, o.overwrite ? RunFolder::Mode::Overwrite : RunFolder::Mode::New,
                                             o.names);
    text = to_json(run.config).dump();
  });
  if (comm.size() == 1) return;
  comm.broadcast(text, 0);
  on_every_rank(comm, [&] {
    if (root) return;
    const std::string source = config_source(o);
    const std::string name = o.config_path.empty() ? kJsonSource : std::filesystem::path(o.config_path).stem().string();
    run.config = parse_train_config(nlohmann::json::parse(text), source + " (from rank 0)", name);
    if (o.threads) run.config.num_threads = *o.threads;
    check_memory(estimate_training_memory(run.config, config_spec(run.config)), limit, source);
  });
}

void resume_run(RunStart& run, const TrainerSettings& o, Communicator& comm, const MemoryLimit& limit) {
  const bool root = comm.rank() == 0;
  run.checkpoint_path = (std::filesystem::path(o.resume_dir) / checkpoint_file_name).string();
  on_every_rank(comm, [&] {
    for (const ConfigOverride& v : o.overrides) {
      if (v.key == "seed")
        throw Error("train: " + o.names.flag(Setting::Seed) + " cannot change a resumed run (it continues the checkpoint's seed)");
      if (v.key == "log_dir")
        throw Error("train: " + o.names.flag(Setting::LogDir) + " cannot be combined with " + o.names.flag(Setting::Resume) +
                    " (the run folder is the one resumed)");
    }
    if (o.overwrite)
      throw Error("train: " + o.names.flag(Setting::Overwrite) + " cannot be combined with " + o.names.flag(Setting::Resume));
    if (!root) return;
    run.folder = std::make_unique<RunFolder>(o.resume_dir, RunFolder::Mode::Resume, o.names);
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
}

}  // namespace

RunStart start_run(const TrainerSettings& o, Communicator& comm) {
  check_settings(o);
  RunStart run;
  const MemoryLimit limit = memory_limit(o.max_memory_gb, o.names);
  // Errors: each step runs on_every_rank, so a bad config is reported once (by rank 0) and every
  // rank leaves with its exit code, none left waiting in a broadcast.
  if (o.resume_dir.empty())
    start_new_run(run, o, comm, limit);
  else
    resume_run(run, o, comm, limit);
  return run;
}

}  // namespace rdsim
