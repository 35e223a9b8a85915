#pragma once
#include <Eigen/Core>
#include <iosfwd>
#include <string>

#include "rdsim/algorithms/running_normalizer.hpp"

// The config's top-level "normalize_observations": the networks of PPO, A2C, TRPO, DQN, SAC, TD3 and
// DDPG see every observation standardised, clip((x - mean) / sqrt(var + 1e-8), -10, 10) per entry,
// with the running mean and variance of the observations the policy met while collecting (what
// Stable-Baselines3's VecNormalize does to observations, as part of the policy instead of the env).
//
// The transform changes only between updates: an algorithm observe()s what it collects and
// refresh()es at the end of each update, so a rollout and the gradient steps that learn from it see
// the same inputs, and replay buffers keep raw observations (HER's relabelled goals are standardised
// like any other). Under MPI a refresh merges every rank's new observations in rank order, so the
// ranks keep the same transform. The transform is part of model.bin (right after the weights), so
// `rdsim replay`, Python `predict` and exports act exactly as the trained policy; checkpoints also
// keep the statistics.
namespace rdsim {

class Communicator;    // rdsim/parallel/communicator.hpp
struct PolicyProgram;  // rdsim/policy/policy_program.hpp

class ObservationNormalizer {
public:
  ObservationNormalizer() = default;  // off: apply() passes inputs through
  explicit ObservationNormalizer(int size);

  bool enabled() const { return size_ > 0; }

  // Network inputs the policy acted on while collecting, one column each, in a fixed order.
  void observe(const Eigen::MatrixXf& observations);
  // Folds the observations since the last refresh (every rank's, under MPI: collective) into the
  // statistics and takes the transform from them (none, inputs unchanged, while fewer than 2 were seen).
  void refresh(Communicator& comm);

  // The standardised `x` (one observation per column) into `out` of the same shape. Only when enabled.
  void apply(const Eigen::MatrixXf& x, Eigen::Ref<Eigen::MatrixXf> out) const;
  // A network's input for observations `x`: standardised into `scratch` when enabled, else `x` times
  // network.input_scale `input_scale` (scaled_input: `x` itself at 1).
  const Eigen::MatrixXf& network_input(const Eigen::MatrixXf& x, float input_scale, Eigen::MatrixXf& scratch) const;

  // What a policy program's input ops are: the standardisation (when on and refreshed), else times
  // network.input_scale `input_scale`.
  void add_input_ops(PolicyProgram& program, float input_scale) const;

  long long count() const { return stats_.count(); }
  const Eigen::VectorXf& mean() const { return mean_; }
  const Eigen::VectorXf& inverse_std() const { return inv_std_; }

  // Nothing when off. The transform; with training_state also the statistics (seen and pending).
  void save(std::ostream& out, bool training_state) const;
  // rdsim::Error naming `source` for another size, non-finite values or a non-positive scale.
  void load(std::istream& in, bool training_state, const std::string& source);

  static constexpr float clip = 10.0f;  // SB3's clip_obs
  static constexpr double epsilon = 1e-8;

private:
  int size_ = 0;
  RunningNormalizer stats_, pending_;
  bool active_ = false;             // false: inputs pass unchanged (fewer than 2 observations at the last refresh)
  Eigen::VectorXf mean_, inv_std_;  // the transform in use
};

}  // namespace rdsim
