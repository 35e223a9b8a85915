// Behaviour cloning (Pomerleau 1991; as in imitation's BC): maximum likelihood of the demonstrated
// actions under the policy, with held-out episodes and early stopping.
#include "rdsim/algorithms/behavior_cloning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/nn/nn.hpp"

namespace rdsim {
namespace {

DemoTransitions gather(const DemoFile& demos, const std::vector<int>& episodes, const ObservationSpace& space,
                       double gamma) {
  int n = 0;
  for (int k : episodes) n += demos.episodes[static_cast<std::size_t>(k)].steps();
  DemoTransitions d;
  d.episodes = static_cast<int>(episodes.size());
  const int action_dim = demos.spec.action.dim();
  d.observations.resize(observation_input_size(space), n);
  d.actions.resize(action_dim, n);
  d.returns.resize(n);
  int at = 0;
  for (int k : episodes) {
    const DemoEpisode& e = demos.episodes[static_cast<std::size_t>(k)];
    for (int t = 0; t < e.steps(); ++t) {
      const auto i = static_cast<std::size_t>(t);
      encode_observation(e.observations[i], space, d.observations.col(at + t));
      if (demos.spec.action.discrete)
        d.actions(0, at + t) = static_cast<float>(e.actions[i].index);
      else
        d.actions.col(at + t) = e.actions[i].values;
    }
    double g = 0.0;  // returns to go, back to front
    for (int t = e.steps() - 1; t >= 0; --t) {
      g = e.rewards[static_cast<std::size_t>(t)] + gamma * g;
      d.returns[at + t] = static_cast<float>(g);
    }
    at += e.steps();
  }
  return d;
}

void shuffle(std::vector<int>& order, Rng& rng) {  // Fisher-Yates from our Rng: the same on every platform
  for (int i = static_cast<int>(order.size()) - 1; i > 0; --i)
    std::swap(order[static_cast<std::size_t>(i)], order[rng.below(static_cast<std::uint64_t>(i) + 1)]);
}

// Columns `idx[begin, begin + count)` of `m`.
Eigen::MatrixXf columns(const Eigen::MatrixXf& m, const std::vector<int>& idx, int begin, int count) {
  Eigen::MatrixXf out(m.rows(), count);
  for (int j = 0; j < count; ++j) out.col(j) = m.col(idx[static_cast<std::size_t>(begin + j)]);
  return out;
}

// One part of the fit (actor or critic): its parameters, optimiser, best epoch and early stop.
struct Part {
  nn::ParamList params;
  std::unique_ptr<nn::Adam> adam;
  double best = std::numeric_limits<double>::infinity();
  double best_train = 0.0, best_extra = 0.0;
  std::string best_weights;
  int since_best = 0;
  bool stopped = false;
  double train = 0.0, val = 0.0, extra = 0.0;  // this epoch's, or the best epoch's once stopped

  Part(nn::ParamList p, double lr) : params(std::move(p)) {
    nn::AdamConfig c;
    c.lr = static_cast<float>(lr);
    adam = std::make_unique<nn::Adam>(params, c);
  }
  // After an epoch: keeps the best weights, and stops with them after `patience` epochs without a better one.
  void judge(double val_loss, double train_loss, double extra_value, int patience, bool has_validation) {
    train = train_loss;
    val = val_loss;
    extra = extra_value;
    if (!has_validation) return;
    if (val_loss < best) {
      best = val_loss;
      best_train = train_loss;
      best_extra = extra_value;
      best_weights = nn::params_to_bytes(params);
      since_best = 0;
    } else if (++since_best >= patience) {
      stop();
    }
  }
  void stop() {
    stopped = true;
    if (best_weights.empty()) return;
    nn::params_from_bytes(params, best_weights, "best epoch");
    train = best_train;
    val = best;
    extra = best_extra;
  }
};

}  // namespace

DemoSplit split_demonstrations(const DemoFile& demos, const ObservationSpace& space, double validation_fraction,
                               double gamma, Rng& rng) {
  const int n = static_cast<int>(demos.episodes.size());
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  shuffle(order, rng);
  int held = static_cast<int>(std::lround(validation_fraction * n));
  if (validation_fraction > 0.0 && n >= 2) held = std::max(held, 1);
  held = std::min(held, n - 1);
  held = std::max(held, 0);
  std::vector<int> validation(order.begin(), order.begin() + held), train(order.begin() + held, order.end());
  std::sort(validation.begin(), validation.end());
  std::sort(train.begin(), train.end());
  return {gather(demos, train, space, gamma), gather(demos, validation, space, gamma)};
}

std::vector<Metrics> fit_to_demonstrations(ActorCritic& policy, const DemoSplit& data, const DemonstrationsConfig& config,
                                           bool fit_critic, Rng& rng) {
  nn::ParamList actor_params, critic_params;
  for (const nn::Param& p : policy.params()) (p.name.rfind("value.", 0) == 0 ? critic_params : actor_params).push_back(p);
  Part actor(actor_params, config.learning_rate), critic(critic_params, config.learning_rate);
  critic.stopped = !fit_critic;

  const DemoTransitions& train = data.train;
  const DemoTransitions& val = data.validation;
  const bool has_val = val.size() > 0;
  const int n = train.size();
  std::vector<int> order(static_cast<std::size_t>(n));
  std::vector<Metrics> rows;
  Rng unused;  // deterministic acting draws nothing
  for (int epoch = 1; epoch <= config.bc_epochs && n > 0 && !(actor.stopped && critic.stopped); ++epoch) {
    std::iota(order.begin(), order.end(), 0);
    shuffle(order, rng);
    double actor_sum = 0.0, critic_sum = 0.0;
    for (int begin = 0; begin < n; begin += config.batch_size) {
      const int b = std::min(config.batch_size, n - begin);
      const Eigen::MatrixXf obs = columns(train.observations, order, begin, b);
      const Eigen::MatrixXf actions = columns(train.actions, order, begin, b);
      Eigen::VectorXf returns(b);
      for (int j = 0; j < b; ++j) returns[j] = train.returns[order[static_cast<std::size_t>(begin + j)]];
      const PolicyEval& ev = policy.evaluate(obs, actions);
      const float inv_b = 1.0f / static_cast<float>(b);
      actor_sum += -ev.log_probs.cast<double>().sum();
      critic_sum += (ev.values - returns).cast<double>().squaredNorm();
      const Eigen::VectorXf d_log_prob = Eigen::VectorXf::Constant(b, actor.stopped ? 0.0f : -inv_b);
      const Eigen::VectorXf d_value = critic.stopped ? Eigen::VectorXf::Zero(b) : Eigen::VectorXf(2.0f * inv_b * (ev.values - returns));
      policy.zero_grad();
      policy.backward(d_log_prob, Eigen::VectorXf(), d_value);
      if (!actor.stopped) actor.adam->step();
      if (!critic.stopped) critic.adam->step();
    }
    // Validation: the loss of each part, and how far the most likely action is from the demonstrated one.
    double actor_val = 0.0, action_error = 0.0, critic_val = 0.0;
    if (has_val) {
      const PolicyEval& ev = policy.evaluate(val.observations, val.actions);
      actor_val = -ev.log_probs.cast<double>().mean();
      critic_val = (ev.values - val.returns).cast<double>().squaredNorm() / val.size();
      ActBatch mode;
      policy.act(val.observations, true, unused, mode);
      if (policy.discrete())
        action_error = (mode.actions.array() != val.actions.array()).cast<double>().mean();
      else
        action_error = std::sqrt((mode.actions - val.actions).cast<double>().colwise().squaredNorm().mean());
    }
    if (!actor.stopped) actor.judge(actor_val, actor_sum / n, action_error, config.patience, has_val);
    if (!critic.stopped) critic.judge(critic_val, critic_sum / n, 0.0, config.patience, has_val);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Metrics row = {{"epoch", epoch},
                   {"actor_loss", actor.train},
                   {"actor_val_loss", has_val ? actor.val : nan},
                   {"actor_val_error", has_val ? actor.extra : nan}};
    if (fit_critic) {
      row.push_back({"critic_loss", critic.train});
      row.push_back({"critic_val_loss", has_val ? critic.val : nan});
    }
    rows.push_back(std::move(row));
  }
  // Out of epochs before the patience ran out: the best epoch's weights all the same.
  if (has_val && !actor.stopped) actor.stop();
  if (has_val && !critic.stopped) critic.stop();
  return rows;
}

}  // namespace rdsim
