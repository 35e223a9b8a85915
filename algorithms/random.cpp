// The random agent: every action uniform in the action space (Discrete: each index equally
// likely; Box: uniform between the bounds, which must be finite), drawn from the
// action-sampling stream. update() only steps the envs, n_steps per env.
#include "rdsim/algorithms/random.hpp"

#include <algorithm>

#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

constexpr std::uint32_t kRandomTag = 0x444E4152;  // "RAND": the model of the random agent holds no weights

class RandomAgent final : public Algorithm {
public:
  RandomAgent(const RandomConfig& config, std::uint64_t seed, const Spec& spec, const std::string& where)
      : cfg_(config), spec_(spec), rng_(Rng::derive(seed, rng_stream::action_sampling)) {
    if (!spec.action.discrete && (!spec.action.low.allFinite() || !spec.action.high.allFinite()))
      throw Error(where + ": algorithm: \"random\" needs finite action bounds, env \"" + spec.env_name + "\" has none");
  }

  std::string name() const override { return "random"; }
  bool data_parallel() const override { return true; }  // no weights: each rank just acts
  bool has_policy_program() const override { return false; }

  Metrics update(VecEnv& envs, const TrainProgress& progress) override {
    const int n = envs.size();
    const long long calls = progress.phase_steps(cfg_.n_steps, n);
    std::vector<Action> actions(static_cast<std::size_t>(n));
    for (long long c = 0; c < calls; ++c) {
      for (Action& a : actions) a = draw(rng_);
      envs.step(actions);
    }
    return {};
  }

  Action act(const Observation& /*observation*/, bool /*deterministic*/, Rng& rng) override { return draw(rng); }

  void save(std::ostream& out, bool training_state) const override {
    write_u32(out, kRandomTag);
    if (training_state) write_string(out, rng_to_bytes(rng_));
  }

  void load(std::istream& in, bool training_state, const std::string& source) override {
    if (read_u32(in, source) != kRandomTag) throw Error(source + ": not a random agent's model");
    if (training_state) rng_ = rng_from_bytes(read_string(in, source), source);
  }

private:
  Action draw(Rng& rng) const {
    if (spec_.action.discrete) return Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(spec_.action.n))));
    Eigen::VectorXf v(spec_.action.dim());
    for (int d = 0; d < v.size(); ++d) v[d] = static_cast<float>(rng.uniform(spec_.action.low[d], spec_.action.high[d]));
    return Action::continuous(std::move(v));
  }

  RandomConfig cfg_;
  Spec spec_;
  Rng rng_;
};

}  // namespace

std::unique_ptr<Algorithm> make_random(const RandomConfig& config, const NetworkConfig& /*network*/, std::uint64_t seed,
                                       const Spec& spec, const std::string& where) {
  return std::make_unique<RandomAgent>(config, seed, spec, where);
}

// No network, no buffer.
void estimate_memory(const RandomConfig&, const AlgorithmConfig&, const Spec&, int, MemoryEstimate&) {}

}  // namespace rdsim
