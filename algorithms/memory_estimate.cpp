// What an algorithm will allocate, from its config alone (estimate_algorithm_memory in
// algorithm_config.hpp). Counts floats of 4 bytes; rounded up where the code keeps extra copies.
#include <algorithm>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/nn/conv.hpp"

namespace rdsim {
namespace {

constexpr double kFloat = 4.0;

// Parameters of a network and the activations one sample keeps in a training pass (floats).
struct Footprint {
  double params = 0.0;
  double activations = 0.0;
  Footprint& operator+=(const Footprint& o) {
    params += o.params;
    activations += o.activations;
    return *this;
  }
};

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

}  // namespace

void estimate_algorithm_memory(const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  struct Visit {
    const AlgorithmConfig& c;
    const Spec& spec;
    int num_envs;
    MemoryEstimate& e;
    void operator()(const PpoConfig& p) const {
      const double rollout = static_cast<double>(p.n_steps) * num_envs;
      on_policy(c.network, spec, num_envs, p.n_steps, std::min<double>(p.batch_size, rollout), "ppo", c.source, e);
    }
    void operator()(const A2cConfig& p) const {
      on_policy(c.network, spec, num_envs, p.n_steps, static_cast<double>(p.n_steps) * num_envs, "a2c", c.source, e);
    }
    // BC: an actor-critic run n_steps x num_envs per update; its training passes (on the
    // demonstrations, batch_size samples) happen before. The demonstrations themselves are bounded by
    // the demo file's reader, not estimated here.
    void operator()(const BcConfig& p) const {
      const double rollout = static_cast<double>(p.n_steps) * num_envs;
      const double batch = c.demonstrations ? std::max<double>(c.demonstrations->batch_size, rollout) : rollout;
      on_policy(c.network, spec, num_envs, p.n_steps, batch, "bc", c.source, e);
    }
    void operator()(const DqnConfig& p) const {
      const Footprint f = q_network(c.network, spec, c.source);
      const double obs = observation_input_size(spec.observation);
      const double obs_bytes = spec.observation.type == ObsType::UInt8 ? obs : obs * kFloat;
      // Online and target networks, gradients, two Adam moments.
      e.add(std::string("Q networks, gradients and optimiser state (") + network_keys(spec) + ")", 5.0 * kFloat * f.params);
      const double replay = static_cast<double>(p.buffer_size) * (2.0 * obs_bytes + 4.0 * kFloat);
      e.add("replay buffer (dqn.buffer_size)", replay);
      e.add("training activations (dqn.batch_size)",
            2.0 * p.batch_size * (3.0 * f.activations + 2.0 * obs) * kFloat + num_envs * (f.activations + obs) * kFloat);
      e.add("checkpoint writing (in-memory copies of the networks and the replay buffer)",
            2.0 * (4.0 * kFloat * f.params + replay));
    }
    void operator()(const SacConfig& p) const {
      actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, 2.0 * spec.action.dim(), false, "sac", e);
    }
    void operator()(const Td3Config& p) const {
      actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, spec.action.dim(), true, "td3", e);
    }
    void operator()(const DdpgConfig& p) const {
      actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, spec.action.dim(), true, "ddpg", e);
    }
    void operator()(const TrpoConfig& p) const {
      // The whole rollout in one pass (the natural-gradient step), plus conjugate-gradient vectors.
      on_policy(c.network, spec, num_envs, p.n_steps, static_cast<double>(p.n_steps) * num_envs, "trpo", c.source, e);
    }
    void operator()(const ArsConfig& p) const {
      policy_search(c.network, spec, num_envs, 2.0 * p.n_delta, false, "ars.n_delta", e);
    }
    void operator()(const CmaEsConfig& p) const {
      const double params = mlp(observation_input_size(spec.observation), c.network.hidden_sizes,
                                spec.action.discrete ? spec.action.n : spec.action.dim()).params;
      const double lambda = p.population_size > 0 ? p.population_size : 4.0 + std::floor(3.0 * std::log(std::max(params, 1.0)));
      policy_search(c.network, spec, num_envs, lambda, true, "cma_es.population_size", e);
    }
    void operator()(const RandomConfig&) const {}  // no network, no buffer
  };
  std::visit(Visit{c, spec, num_envs, e}, c.params);
}

}  // namespace rdsim
