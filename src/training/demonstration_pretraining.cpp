#include "demonstration_pretraining.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "rdsim/algorithms/demonstration_replay.hpp"
#include "rdsim/algorithms/demonstration_scatter.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_fit.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {

DemoFile read_demonstrations(const TrainConfig& config) {
  try {
    return read_demo_file(config.algorithm.demonstrations->file);
  } catch (const Error& e) {  // which key of which config named the file (a relative one: from the config's folder)
    throw Error(config.source + ": demonstrations.file: " + e.what());
  }
}

std::shared_ptr<const DemoFile> starting_demonstrations(const TrainConfig& config, std::shared_ptr<const DemoFile> demos) {
  const auto& dc = config.algorithm.demonstrations;
  if (!dc || dc->start_file.empty()) return demos;
  try {
    return std::make_shared<const DemoFile>(read_demo_file(dc->start_file));
  } catch (const Error& e) {
    throw Error(config.source + ": demonstrations.start_file: " + e.what());
  }
}

void learn_from_demonstrations(const TrainConfig& config, const DemoFile& demos, Algorithm& algo, const Spec& spec,
                               bool resume, const std::filesystem::path& dir, bool quiet) {
  const DemonstrationsConfig& dc = *config.algorithm.demonstrations;
  if (dc.shift > 0.0 && planar_position_rows(spec).empty())
    throw Error(config.source + ": demonstrations.shift: env \"" + spec.env_name +
                "\" has no world positions to shift (a goal env with Cartesian actions: push, pick_and_place, stack, "
                "reach_goal; not with control \"joints\")");
  if (dc.scatter > 0.0 && !DemonstrationScatter::supported(spec))
    throw Error(config.source + ": demonstrations.scatter: env \"" + spec.env_name +
                "\" has no objects to scatter (a goal env with one to seven objects in its observation: push, pick_and_place, stack)");
  check_demos_fit(demos, to_json(config.env), spec);
  if (demos.episodes.empty()) throw Error(dc.file + ": holds no episode to learn from");
  Rng rng = Rng::derive(config.seed, rng_stream::demonstrations);
  const std::vector<Metrics> rows = algo.learn_from_demonstrations(demos, dc, rng, !resume);
  if (rows.empty() || dir.empty()) return;
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

}  // namespace rdsim
