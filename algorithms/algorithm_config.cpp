#include "rdsim/algorithms/algorithm_config.hpp"

#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

// The name of each AlgorithmParams alternative in configs, in the variant's order.
constexpr const char* kNames[] = {"ppo", "a2c", "dqn", "sac", "td3", "ddpg", "trpo", "ars", "cma_es", "random", "bc"};
static_assert(std::size(kNames) == std::variant_size_v<AlgorithmParams>, "one name per AlgorithmParams alternative");

template <std::size_t I = 0>
AlgorithmParams params_by_index(std::size_t index) {
  if constexpr (I < std::variant_size_v<AlgorithmParams>) {
    if (index == I) return AlgorithmParams(std::in_place_index<I>);
    return params_by_index<I + 1>(index);
  } else {
    return AlgorithmParams{};
  }
}

std::string known_names() {
  std::string known;
  for (const char* n : kNames) known += (known.empty() ? "" : ", ") + ("\"" + std::string(n) + "\"");
  return known;
}

// Whether `algorithm` uses the "demonstrations" key `key` (demonstrations.hpp says who uses what).
bool uses_demonstrations_key(const std::string& algorithm, const std::string& key) {
  if (key == "start_fraction" || key == "start_file" || key == "start_redraw") return algorithm != "bc";  // the training envs' starts (demonstration_starts.hpp)
  if (is_off_policy_actor_critic(algorithm))  // sac, td3, ddpg (off_policy.hpp)
    return key == "file" || key == "bc_epochs" || key == "demo_fraction" || key == "bc_weight" || key == "shift" ||
           key == "scatter" || key == "scatter_goal";
  if (key == "demo_fraction" || key == "large_margin" || key == "margin" || key == "margin_weight") return algorithm == "dqn";
  if (key == "fit_critic" || key == "bc_weight" || key == "bc_weight_decay") return algorithm != "dqn" && algorithm != "bc";
  return key != "shift" && key != "scatter" && key != "scatter_goal";
}

// "demonstrations": read when present; keys the algorithm would ignore are errors.
void read_demonstrations(ConfigReader& r, const std::string& name, AlgorithmConfig& c) {
  r.accept("demonstrations");  // known, so that a misspelt key gets "did you mean"
  if (!r.has("demonstrations")) {
    if (name == "bc") r.fail("demonstrations", "missing: bc learns from demonstrations (expected {\"file\": \"F.demo\"})");
    return;
  }
  ConfigReader section = r.child("demonstrations");
  for (const std::string& key : section.keys())
    if (!uses_demonstrations_key(name, key)) section.fail(key, "has no effect with \"algorithm\": \"" + name + "\"");
  DemonstrationsConfig demos;
  config::read_fields(section, demos);
  c.demonstrations = demos;
}

// "her": read when present, for the off-policy algorithms only (whether the env has goals is
// checked when the algorithm meets the env's spec).
void read_her(ConfigReader& r, const std::string& name, AlgorithmConfig& c) {
  r.accept("her");  // known, so that a misspelt key gets "did you mean"
  if (!r.has("her")) return;
  if (!takes_her(name))
    r.fail("her", "has no effect with \"algorithm\": \"" + name +
                      "\" (hindsight experience replay relabels a replay buffer: sac, td3, ddpg or dqn)");
  ConfigReader section = r.child("her");
  HerConfig her;
  config::read_fields(section, her);
  c.her = her;
}

}  // namespace

bool is_off_policy_actor_critic(const std::string& algorithm) {
  return algorithm == "sac" || algorithm == "td3" || algorithm == "ddpg";
}

bool takes_her(const std::string& algorithm) { return is_off_policy_actor_critic(algorithm) || algorithm == "dqn"; }

bool takes_observation_normalization(const std::string& algorithm) {
  return algorithm == "ppo" || algorithm == "a2c" || algorithm == "trpo" || algorithm == "dqn" ||
         is_off_policy_actor_critic(algorithm);
}

std::string AlgorithmConfig::name() const { return kNames[params.index()]; }

std::vector<std::string> algorithm_names() { return {std::begin(kNames), std::end(kNames)}; }

AlgorithmParams default_algorithm_params(const std::string& name) {
  for (std::size_t i = 0; i < std::size(kNames); ++i)
    if (name == kNames[i]) return params_by_index(i);
  throw Error("unknown algorithm \"" + name + "\" (known: " + known_names() + ")");
}

AlgorithmConfig read_algorithm_config(ConfigReader& r) {
  AlgorithmConfig c;
  c.source = r.where();
  std::string name = kNames[0];
  r.read_choice("algorithm", name, algorithm_names());
  c.params = default_algorithm_params(name);
  ConfigReader network = r.child("network");
  config::read_fields(network, c.network);
  std::visit(
      [&](auto& params) {
        ConfigReader section = r.child(name);
        config::read_fields(section, params);
      },
      c.params);
  for (const char* other : kNames) {
    if (other != name && r.has(other))
      r.fail(other, "has no effect with \"algorithm\": \"" + name + "\" (expected a \"" + name + "\" object, or none)");
  }
  read_demonstrations(r, name, c);
  read_her(r, name, c);
  r.accept("normalize_observations");
  if (r.has("normalize_observations")) {
    r.read("normalize_observations", c.normalize_observations);
    if (c.normalize_observations && !takes_observation_normalization(name))
      r.fail("normalize_observations",
             "has no effect with \"algorithm\": \"" + name + "\"" +
                 (name == "ars" || name == "cma_es" ? " (it has its own: " + name + ".normalize_observations)"
                                                    : std::string(" (ppo, a2c, trpo, dqn, sac, td3 and ddpg take it)")));
  }
  return c;
}

void write_algorithm_config(const AlgorithmConfig& c, nlohmann::json& out) {
  out["algorithm"] = c.name();
  out["network"] = config::write_fields(c.network);
  std::visit([&](const auto& params) { out[c.name()] = config::write_fields(params); }, c.params);
  if (c.demonstrations) {
    const nlohmann::json all = config::write_fields(*c.demonstrations);
    nlohmann::json demos = nlohmann::json::object();
    for (const auto& [key, value] : all.items())
      if (uses_demonstrations_key(c.name(), key)) demos[key] = value;
    out["demonstrations"] = std::move(demos);
  }
  if (c.her) out["her"] = config::write_fields(*c.her);
  if (c.normalize_observations) out["normalize_observations"] = true;
}

void check_trainable(const AlgorithmConfig& c, const Spec& spec) {
  if (spec.observation.vector_size > 0)
    throw Error(c.source + ": env.observation: \"raw_pixels\" on goal env \"" + spec.env_name +
                "\" gives camera images with the goals beside them, which rdsim's algorithms do not train on yet: "
                "expected \"ground_truth\" (or train from Python: Stable-Baselines3's MultiInputPolicy takes the Dict observation)");
}

std::unique_ptr<Algorithm> make_algorithm(const AlgorithmConfig& c, std::uint64_t seed, const Spec& spec) {
  check_trainable(c, spec);
  struct Make {
    const AlgorithmConfig& c;
    std::uint64_t seed;
    const Spec& spec;
    std::unique_ptr<Algorithm> operator()(const PpoConfig& p) const { return make_ppo(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const A2cConfig& p) const { return make_a2c(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const DqnConfig& p) const { return make_dqn(p, c.network, seed, spec, c.source, c.her); }
    std::unique_ptr<Algorithm> operator()(const SacConfig& p) const { return make_sac(p, c.network, seed, spec, c.source, c.her); }
    std::unique_ptr<Algorithm> operator()(const Td3Config& p) const { return make_td3(p, c.network, seed, spec, c.source, c.her); }
    std::unique_ptr<Algorithm> operator()(const DdpgConfig& p) const { return make_ddpg(p, c.network, seed, spec, c.source, c.her); }
    std::unique_ptr<Algorithm> operator()(const TrpoConfig& p) const { return make_trpo(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const ArsConfig& p) const { return make_ars(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const CmaEsConfig& p) const { return make_cma_es(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const RandomConfig& p) const { return make_random(p, c.network, seed, spec, c.source); }
    std::unique_ptr<Algorithm> operator()(const BcConfig& p) const { return make_bc(p, c.network, seed, spec, c.source); }
  };
  std::unique_ptr<Algorithm> algorithm = std::visit(Make{c, seed, spec}, c.params);
  if (c.normalize_observations) algorithm->enable_observation_normalization();
  return algorithm;
}

}  // namespace rdsim
