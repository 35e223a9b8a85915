#pragma once
#include <Eigen/Core>
#include <vector>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/demonstrations.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/demos/demo_file.hpp"

// Supervised learning from demonstrations: the actor fitted to the demonstrated actions and the
// critic to the demonstrated returns. `bc` is this alone; PPO and A2C start from it.
namespace rdsim {

// Steps of some demonstration episodes in network-input form (observation_batch.hpp), one column each.
struct DemoTransitions {
  Eigen::MatrixXf observations;  // observation inputs x N
  Eigen::MatrixXf actions;       // action dim x N (Discrete: the index as a float)
  Eigen::VectorXf returns;       // discounted return from that step to the end of its episode
  int episodes = 0;

  int size() const { return static_cast<int>(observations.cols()); }
};

struct DemoSplit {
  DemoTransitions train, validation;
};

// Holds out whole episodes (steps of one episode are alike, so a split by steps would flatter the
// fit): round(validation_fraction x episodes) of them, at least one when the fraction is positive
// and there are two episodes or more, never all; which ones is drawn from `rng`. Returns use `gamma`.
DemoSplit split_demonstrations(const DemoFile& demos, const ObservationSpace& space, double validation_fraction,
                               double gamma, Rng& rng);

// Fits `policy` to `data` for up to config.bc_epochs epochs of shuffled minibatches (config.batch_size,
// Adam at config.learning_rate; order drawn from `rng`):
//   actor   negative log-likelihood of the demonstrated actions (cross-entropy for Discrete,
//           Gaussian log-likelihood with the trained log std for Box); every parameter except the
//           value head's;
//   critic  (with `fit_critic`) squared error of V against the returns; the value head only (a shared
//           trunk follows the actor).
// With a validation set each part stops after config.patience epochs without a lower validation
// loss and gets the weights of its best epoch back. One Metrics row per epoch: epoch, actor_loss,
// actor_val_loss, actor_val_error (Discrete: share of validation steps whose most likely action is
// not the demonstrated one; Box: RMS distance of the mean action from it), and with the critic
// critic_loss and critic_val_loss. A part that has stopped repeats its best values.
std::vector<Metrics> fit_to_demonstrations(ActorCritic& policy, const DemoSplit& data, const DemonstrationsConfig& config,
                                           bool fit_critic, Rng& rng);

}  // namespace rdsim
