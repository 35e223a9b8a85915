// The building blocks of the algorithms' memory estimates (algorithm_memory.hpp; each algorithm's
// own estimate sits beside it in algorithms/<name>.cpp). Counts floats of 4 bytes; rounded up where
// the code keeps extra copies.
#include "memory_footprint.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/vecenv/observation_batch.hpp"

namespace rdsim::memory {

Footprint mlp(double in, const std::vector<int>& hidden, double out) {
  Footprint f;
  double prev = in;
  for (int h : hidden) {
    f.params += (prev + 1.0) * h;
    f.activations += 2.0 * h;  // pre-activation and activation
    prev = h;
  }
  f.params += (prev + 1.0) * out;
  f.activations += out;
  return f;
}

// Convs then the dense head; the same shape checks as building it (an image too small for the
// kernels is named here, before anything is allocated).
Footprint cnn(const nn::CnnShape& shape, const std::string& where) {
  Footprint f;
  nn::ImageShape image = shape.input;
  for (const nn::ConvSpec& c : shape.convs) {
    const nn::ImageShape out = nn::conv_output_shape(image, c, where);
    f.params += (static_cast<double>(c.kernel) * c.kernel * image.channels + 1.0) * c.out_channels;
    f.activations += 2.0 * out.size();
    image = out;
  }
  f += mlp(image.size(), shape.hidden_sizes, shape.output_size);
  return f;
}

Footprint actor_critic(const NetworkConfig& n, const Spec& spec, const std::string& where) {
  const double obs = observation_input_size(spec.observation);
  const double policy_out = spec.action.discrete ? spec.action.n : spec.action.dim();
  if (is_image_space(spec.observation)) {
    nn::CnnShape shape = cnn_shape(n.cnn, spec.observation, 1, where + ": network.cnn");
    if (shape.hidden_sizes.empty()) return cnn(shape, where + ": network.cnn");
    shape.output_size = shape.hidden_sizes.back();
    shape.hidden_sizes.pop_back();
    Footprint f = cnn(shape, where + ": network.cnn");
    f += mlp(shape.output_size, {}, policy_out + 1.0);
    return f;
  }
  if (n.shared && !n.hidden_sizes.empty()) {
    const std::vector<int> trunk(n.hidden_sizes.begin(), n.hidden_sizes.end() - 1);
    Footprint f = mlp(obs, trunk, n.hidden_sizes.back());
    f += mlp(n.hidden_sizes.back(), {}, policy_out + 1.0);
    return f;
  }
  Footprint f = mlp(obs, n.hidden_sizes, policy_out);
  f += mlp(obs, n.hidden_sizes, 1.0);
  return f;
}

Footprint q_network(const NetworkConfig& n, const Spec& spec, const std::string& where) {
  const double actions = spec.action.discrete ? spec.action.n : 1.0;
  if (is_image_space(spec.observation))
    return cnn(cnn_shape(n.cnn, spec.observation, static_cast<int>(actions), where + ": network.cnn"), where + ": network.cnn");
  return mlp(observation_input_size(spec.observation), n.hidden_sizes, actions);
}

const char* network_keys(const Spec& spec) {
  return is_image_space(spec.observation) ? "network.cnn" : "network.hidden_sizes";
}

// PPO and A2C: one actor-critic, Adam/RMSprop state, a rollout of n_steps x num_envs samples,
// training passes over `batch` samples.
void on_policy(const NetworkConfig& n, const Spec& spec, int num_envs, int n_steps, double batch, const char* algo,
               const std::string& where, MemoryEstimate& e) {
  const Footprint f = actor_critic(n, spec, where);
  const double obs = observation_input_size(spec.observation);
  const double samples = static_cast<double>(n_steps) * num_envs;
  // Value, gradient and two optimiser moments per parameter.
  e.add(std::string("network weights, gradients and optimiser state (") + network_keys(spec) + ")", 4.0 * kFloat * f.params);
  e.add(std::string("rollout buffer (") + algo + ".n_steps x num_envs)", samples * (obs + spec.action.dim() + 8.0) * kFloat);
  // Forward caches and their gradients, plus the minibatch's inputs.
  e.add(std::string("training activations (") + algo + (std::string(algo) == "ppo" ? ".batch_size)" : ".n_steps x num_envs)"),
        batch * (3.0 * f.activations + 2.0 * obs) * kFloat + num_envs * (2.0 * f.activations + obs) * kFloat);
  e.add("checkpoint writing (in-memory copies of weights and optimiser state)", 2.0 * 3.0 * kFloat * f.params);
}

// SAC, TD3, DDPG: an actor (policy_out outputs), two critics on (observation, action), their target
// copies, Adam state, a replay buffer of Box actions, training passes over batch_size samples.
void actor_critics(const NetworkConfig& n, const Spec& spec, int num_envs, long long buffer_size, int batch_size,
                   double policy_out, bool target_actor, const char* algo, MemoryEstimate& e) {
  const double obs = observation_input_size(spec.observation);
  const double act = spec.action.dim();
  const Footprint actor = mlp(obs, n.hidden_sizes, policy_out);
  const Footprint critic = mlp(obs + act, n.hidden_sizes, 1.0);
  // Weights, gradient, two Adam moments (+ a target copy): 4 or 5 floats per parameter.
  const double weights = (target_actor ? 5.0 : 4.0) * actor.params + 2.0 * 5.0 * critic.params;
  e.add("actor and critic networks, targets, gradients and optimiser state (network.hidden_sizes)", weights * kFloat);
  const double replay = static_cast<double>(buffer_size) * (2.0 * obs + act + 3.0) * kFloat;
  e.add(std::string("replay buffer (") + algo + ".buffer_size)", replay);
  // Actor pass, online and target critic passes on both critics, their gradients.
  e.add(std::string("training activations (") + algo + ".batch_size)",
        static_cast<double>(batch_size) * (3.0 * actor.activations + 8.0 * critic.activations + 4.0 * (obs + act)) * kFloat +
            num_envs * (actor.activations + obs) * kFloat);
  e.add("checkpoint writing (in-memory copies of the networks and the replay buffer)", 2.0 * (weights * kFloat + replay));
}

// ARS, CMA-ES: one flat policy, `copies` parameter vectors (perturbations, candidates) and,
// for CMA-ES, the covariance and its eigenvectors (doubles, parameters squared).
void policy_search(const NetworkConfig& n, const Spec& spec, int num_envs, double copies, bool covariance,
                   const char* keys, MemoryEstimate& e) {
  const double obs = observation_input_size(spec.observation);
  const double out = spec.action.discrete ? spec.action.n : spec.action.dim();
  const Footprint f = mlp(obs, n.hidden_sizes, out);
  e.add("policy parameters and candidates (network.hidden_sizes, " + std::string(keys) + ")",
        (copies + 4.0) * f.params * 8.0 + num_envs * (f.activations + obs) * kFloat);
  if (covariance) e.add("CMA-ES covariance and eigenvectors (network.hidden_sizes)", 3.0 * f.params * f.params * 8.0);
}

}  // namespace rdsim::memory

namespace rdsim {

void estimate_algorithm_memory(const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  check_trainable(c, spec);  // before a size that the algorithm could never reach
  std::visit([&](const auto& params) { estimate_memory(params, c, spec, num_envs, e); }, c.params);
  // Hindsight replay: an episode start (8 bytes) and length (4 bytes) per buffer slot, and twice that
  // while a checkpoint is written (as the replay buffer above).
  if (c.her)
    std::visit(
        [&](const auto& params) {
          if constexpr (requires { params.buffer_size; })  // the replay-buffer algorithms
            e.add("hindsight replay bookkeeping (her)", 3.0 * 12.0 * static_cast<double>(params.buffer_size));
        },
        c.params);
}

}  // namespace rdsim
