#include "rdsim/export/policy_export.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "rdsim/policy/policy_program.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/export/onnx_export.hpp"
#include "rdsim/training/saved_policy.hpp"
#include "rdsim/vecenv/observation_batch.hpp"

namespace rdsim {
namespace {

constexpr int checked_observations = 256;
constexpr double tolerance = 1e-5;

// The largest |program - act()| over `n` random observations (vectors: standard normal entries, so
// the networks' inputs cover their usual range and beyond; images: uniform bytes); a discrete
// disagreement counts as infinity.
double compare_with_act(const PolicyProgram& program, Algorithm& algo, const ObservationSpace& space, int n) {
  Rng rng(20261128);
  std::vector<Observation> observations(static_cast<std::size_t>(n));
  Eigen::MatrixXf x(program.input_size, n);
  for (int c = 0; c < n; ++c) {
    Observation& obs = observations[static_cast<std::size_t>(c)];
    if (program.pixels) {
      obs.pixels.resize(static_cast<std::size_t>(space.size()));
      for (auto& p : obs.pixels) p = static_cast<std::uint8_t>(rng.below(256));
    } else {
      obs.values.resize(space.size());
      for (Eigen::Index k = 0; k < obs.values.size(); ++k) obs.values[k] = static_cast<float>(rng.normal());
    }
    encode_observation(obs, space, x.col(c));
  }
  const Eigen::MatrixXf y = run_policy_program(program, x);
  double worst = 0.0;
  Rng unused(0);
  for (int c = 0; c < n; ++c) {
    const Action a = algo.act(observations[static_cast<std::size_t>(c)], true, unused);
    if (program.discrete) {
      if (a.index != static_cast<int>(y(0, c))) worst = INFINITY;
    } else {
      worst = std::max(worst, static_cast<double>((a.values - y.col(c)).cwiseAbs().maxCoeff()));
    }
  }
  return worst;
}

}  // namespace

ExportSummary export_onnx(const std::string& model_path, const std::string& out_path) {
  SavedPolicy saved = load_saved_policy(model_path);
  PolicyProgram program;
  try {
    program = saved.algorithm->policy_program();
  } catch (const Error& e) {
    throw Error(model_path + ": " + e.what());
  }
  ExportSummary s;
  s.algorithm = saved.config.algorithm.name();
  s.env = saved.config.env.name;
  s.spec = describe_spec(saved.spec);
  s.checked = checked_observations;
  s.max_difference = compare_with_act(program, *saved.algorithm, saved.spec.observation, checked_observations);
  if (!(s.max_difference <= tolerance))
    throw Error(model_path + ": export: the exported program's actions differ from rdsim's (by " +
                std::to_string(s.max_difference) + "); please report this as a bug");
  const std::map<std::string, std::string> metadata = {
      {"rdsim_version", RDSIM_VERSION}, {"algorithm", s.algorithm}, {"env", s.env},
      {"spec", s.spec},                 {"normalize_observations", saved.config.algorithm.normalize_observations ? "true" : "false"},
      {"model_file", model_path}};
  const std::string bytes = onnx_model_bytes(program, metadata);
  write_file_atomic(out_path, bytes);
  s.bytes = static_cast<long long>(bytes.size());
  return s;
}

}  // namespace rdsim
