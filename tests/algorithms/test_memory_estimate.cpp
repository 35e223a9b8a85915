// Each algorithm's memory estimate (estimate_algorithm_memory; algorithms/<name>.cpp) against what
// the algorithm really holds: its checkpoint (weights and optimiser state; replay methods: the
// stored transitions) and the rollout buffers of its shape. An estimate may be generous, never short.
#include <catch2/catch.hpp>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rdsim/algorithms/rollout.hpp"
#include "rdsim/core/memory_estimate.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

constexpr int kEnvs = 2;

// The bytes of the estimate's items whose description starts with `prefix`.
double item(const MemoryEstimate& e, const std::string& prefix) {
  double bytes = 0.0;
  for (const MemoryItem& i : e.items())
    if (i.what.rfind(prefix, 0) == 0) bytes += i.bytes;
  return bytes;
}

MemoryEstimate estimate(const Setup& s, const Spec& spec) {
  MemoryEstimate e;
  estimate_algorithm_memory(algorithm_config(s), spec, kEnvs, e);
  return e;
}

double checkpoint_bytes(const Algorithm& algo) {
  std::ostringstream out;
  algo.save(out, true);
  return static_cast<double>(out.str().size());
}

// What an algorithm holds after `steps` env steps on sign envs: its checkpoint before and after.
struct Held {
  double at_start = 0.0, after = 0.0;
};

Held train(const Setup& s, bool discrete, long long steps) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < kEnvs; ++i) envs.push_back(std::make_unique<toy::SignEnv>(discrete));
  VecEnv vec(std::move(envs), s.seed);
  auto algo = make_algorithm(s, vec.spec());
  Held h;
  h.at_start = checkpoint_bytes(*algo);
  while (vec.timesteps() < steps) algo->update(vec, {vec.timesteps(), steps});
  h.after = checkpoint_bytes(*algo);
  return h;
}

Spec sign_spec(bool discrete) { return toy::SignEnv(discrete).spec(); }

Setup with_network(const std::string& algorithm) {
  Setup s;
  s.algorithm = algorithm;
  s.source = "memory.json";
  s.seed = 1;
  s.network.hidden_sizes = {64, 64};
  return s;
}

// The rollout buffer an on-policy algorithm fills: n_steps x kEnvs samples of the spec's shape.
double rollout_bytes(int n_steps, const Spec& spec) {
  RolloutBuffer r;
  const int obs = static_cast<int>(spec.observation.low.size());
  r.resize(n_steps, kEnvs, obs, spec.action.discrete ? 1 : spec.action.dim());
  const auto floats = r.observations.size() + r.actions.size() + r.log_probs.size() + r.values.size() +
                      r.rewards.size() + r.final_values.size() + r.last_values.size() + r.advantages.size() +
                      r.returns.size();
  return 4.0 * static_cast<double>(floats) + static_cast<double>(r.ends.size());
}

// The weights item covers the checkpoint's weights and optimiser state (it also counts gradients).
void check_weights(const MemoryEstimate& e, const std::string& prefix, double checkpoint) {
  INFO(prefix << ": estimated " << item(e, prefix) << " bytes, checkpoint " << checkpoint);
  CHECK(item(e, prefix) >= checkpoint);
  CHECK(item(e, prefix) <= 4.0 * checkpoint);
}

// The rollout item covers the real rollout buffer, within 60% more.
void check_rollout(const MemoryEstimate& e, int n_steps, const Spec& spec) {
  const double real = rollout_bytes(n_steps, spec);
  INFO("rollout: estimated " << item(e, "rollout buffer") << " bytes, allocated " << real);
  CHECK(item(e, "rollout buffer") >= real);
  CHECK(item(e, "rollout buffer") <= 1.6 * real);
}

// The replay item is the stored transitions of a full buffer, as its checkpoint holds them.
void check_replay(const MemoryEstimate& e, const Held& h) {
  const double stored = h.after - h.at_start;
  INFO("replay: estimated " << item(e, "replay buffer") << " bytes, stored " << stored);
  CHECK(item(e, "replay buffer") >= stored);
  CHECK(item(e, "replay buffer") <= 1.2 * stored);
}

// Small buffers and batches for every replay method (each uses its own object).
template <class... Params>
void small_replay(Params&... params) {
  ((params.buffer_size = 400, params.learning_starts = 50, params.batch_size = 32), ...);
}

}  // namespace

TEST_CASE("each on-policy method's memory estimate covers its weights and rollout", "[memory]") {
  for (const char* name : {"ppo", "a2c", "trpo"}) {
    DYNAMIC_SECTION(name) {
      Setup s = with_network(name);
      s.ppo.n_steps = s.ppo.batch_size = s.a2c.n_steps = s.trpo.n_steps = 32;
      const MemoryEstimate e = estimate(s, sign_spec(true));
      check_weights(e, "network weights", train(s, true, 2LL * 32 * kEnvs).after);  // after two updates
      check_rollout(e, 32, sign_spec(true));
    }
  }
}

TEST_CASE("BC's memory estimate covers its rollout", "[memory]") {
  Setup s = with_network("bc");
  s.bc.n_steps = 32;
  check_rollout(estimate(s, sign_spec(true)), 32, sign_spec(true));
}

TEST_CASE("each replay method's memory estimate covers its networks and a full replay buffer", "[memory]") {
  const struct {
    const char* name;
    bool discrete;
    const char* weights;  // the estimate's item for the networks
  } methods[] = {{"dqn", true, "Q networks"},
                 {"sac", false, "actor and critic networks"},
                 {"td3", false, "actor and critic networks"},
                 {"ddpg", false, "actor and critic networks"}};
  for (const auto& m : methods) {
    DYNAMIC_SECTION(m.name) {
      Setup s = with_network(m.name);
      small_replay(s.dqn, s.sac, s.td3, s.ddpg);
      const MemoryEstimate e = estimate(s, sign_spec(m.discrete));
      const Held h = train(s, m.discrete, 600);  // fills the buffer of 400
      check_weights(e, m.weights, h.at_start);
      check_replay(e, h);
    }
  }
}

TEST_CASE("ARS's memory estimate covers its policy and candidates", "[memory]") {
  Setup s = with_network("ars");
  s.ars.n_delta = 4;
  const MemoryEstimate e = estimate(s, sign_spec(true));
  const double held = train(s, true, 400).after;
  INFO("estimated " << item(e, "policy parameters") << " bytes, checkpoint " << held);
  CHECK(item(e, "policy parameters") >= held);
}

TEST_CASE("CMA-ES's memory estimate covers its candidates and covariance", "[memory]") {
  Setup s = with_network("cma_es");
  s.network.hidden_sizes = {8};  // the covariance is parameters squared
  s.cma_es.population_size = 6;
  const MemoryEstimate e = estimate(s, sign_spec(true));
  const double held = train(s, true, 400).after;
  INFO("estimated " << e.total() << " bytes, checkpoint " << held);
  CHECK(item(e, "CMA-ES covariance") + item(e, "policy parameters") >= held);
}

TEST_CASE("random actions need no memory of their own", "[memory]") {
  CHECK(estimate(with_network("random"), sign_spec(true)).items().empty());
}
