#pragma once
#include <Eigen/Core>

// The pieces of Deep Q-Learning (algorithms/dqn.cpp) that are worth testing on their own.
// The algorithm itself is created through make_dqn() (include/rdsim/algorithm.hpp).
namespace rdsim::dqn {

// One-step TD targets y_j = r_j + gamma * (1 - terminated_j) * Q_target(s'_j, a*_j).
// a*_j = argmax_a next_q_target(:, j), or with double Q-learning (next_q_online != nullptr)
// a*_j = argmax_a next_q_online(:, j), evaluated by the target network (van Hasselt et al.).
// Q matrices are actions x batch. Truncated transitions carry terminated = 0: they bootstrap.
Eigen::VectorXf td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                           const Eigen::MatrixXf& next_q_target, const Eigen::MatrixXf* next_q_online,
                           float gamma);

// Mean over the batch of a TD loss of (prediction - target) and its gradient w.r.t. each
// prediction (already divided by the batch size).
struct TdLoss {
  float loss = 0.0f;
  Eigen::VectorXf grad;
};
// Huber / smooth-L1 with threshold 1: 0.5 d^2 for |d| <= 1, |d| - 0.5 beyond.
TdLoss huber_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target);
// 0.5 d^2 everywhere (so both losses agree for small errors).
TdLoss squared_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target);

// Linear exploration schedule: `initial` at step 0 falling to `final` at fraction * total steps,
// `final` afterwards (Stable-Baselines3's).
double epsilon_at(long long timesteps, long long total_timesteps, double fraction, double initial,
                  double final_eps);

}  // namespace rdsim::dqn
