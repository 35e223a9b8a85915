#include <catch2/catch.hpp>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/trpo.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/nn.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

Setup trpo_setup(std::uint64_t seed) {
  Setup c;
  c.algorithm = "trpo";
  c.seed = seed;
  c.source = "sign_trpo.json";
  c.network.hidden_sizes = {16, 16};
  c.trpo.n_steps = 64;
  c.trpo.batch_size = 64;
  c.trpo.n_critic_updates = 5;
  c.trpo.target_kl = 0.02;
  return c;
}

Eigen::MatrixXf random_matrix(int rows, int cols, Rng& rng) {
  Eigen::MatrixXf m(rows, cols);
  for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = static_cast<float>(rng.normal());
  return m;
}

}  // namespace

TEST_CASE("conjugate gradient solves a symmetric positive definite system", "[trpo]") {
  Rng rng(1);
  const Eigen::MatrixXf m = random_matrix(6, 6, rng);
  const Eigen::MatrixXf a = m * m.transpose() + Eigen::MatrixXf::Identity(6, 6);
  const Eigen::VectorXf b = random_matrix(6, 1, rng);
  int products = 0;
  const Eigen::VectorXf x = trpo::conjugate_gradient(
      [&](const Eigen::VectorXf& v) -> Eigen::VectorXf {
        ++products;
        return a * v;
      },
      b, 20);
  CHECK((a * x - b).norm() < 1e-3f * b.norm());
  CHECK(products <= 7);  // exact arithmetic needs at most n steps; it stops once the residual is tiny
  const Eigen::VectorXf two = trpo::conjugate_gradient([&](const Eigen::VectorXf& v) -> Eigen::VectorXf { return a * v; }, b, 2);
  CHECK((a * two - b).norm() > (a * x - b).norm());  // max_steps bounds the work
}

TEST_CASE("Fisher-vector products match the curvature of the KL divergence", "[trpo]") {
  for (bool discrete : {true, false}) {
    const Spec spec = toy::SignEnv(discrete).spec();
    NetworkConfig net;
    net.hidden_sizes = {5};
    net.log_std_init = -0.3;
    Rng init(3), rng(4);
    ActorCritic policy(spec, net, init);
    const nn::ParamList params = policy.policy_params();
    const Eigen::VectorXf theta = nn::flatten_values(params);
    // Move the policy head's output layer off its tiny init so the distributions are not uniform.
    nn::assign_values(params, theta + 0.5f * random_matrix(static_cast<int>(theta.size()), 1, rng));
    const Eigen::VectorXf theta0 = nn::flatten_values(params);
    const Eigen::MatrixXf obs = random_matrix(2, 7, rng);
    Eigen::MatrixXf actions = discrete ? Eigen::MatrixXf::Zero(1, 7) : random_matrix(1, 7, rng);
    policy.evaluate(obs, actions);
    const ActorCritic::Distributions old = policy.distributions();
    const Eigen::VectorXf u = random_matrix(static_cast<int>(theta0.size()), 1, rng);
    const Eigen::VectorXf v = random_matrix(static_cast<int>(theta0.size()), 1, rng);
    const Eigen::VectorXf fv = policy.fisher_vector_product(v);
    CHECK(policy.mean_kl(old) == Approx(0.0).margin(1e-6));
    // KL(old || theta0 + d) = 0.5 d^T F d + T(d, d, d) + O(|d|^4): the four-point mixed difference
    // cancels the odd third-order term, so u^T F v = (KL(e(u+v)) - KL(e(u-v)) - KL(-e(u-v)) + KL(-e(u+v))) / (4 e^2).
    const float e = 5e-3f;
    const auto kl_at = [&](const Eigen::VectorXf& d) {
      nn::assign_values(params, theta0 + d);
      policy.evaluate(obs, actions);
      return policy.mean_kl(old);
    };
    const double numeric =
        (kl_at(e * (u + v)) - kl_at(e * (u - v)) - kl_at(-e * (u - v)) + kl_at(-e * (u + v))) / (4.0 * e * e);
    INFO((discrete ? "categorical" : "gaussian") << ": u^T F v = " << u.dot(fv) << ", finite differences " << numeric);
    CHECK(u.dot(fv) == Approx(numeric).epsilon(0.05));
  }
}

TEST_CASE("TRPO learns the toy task within its trust region", "[trpo]") {
  for (bool discrete : {true, false}) {
    Setup setup = trpo_setup(1);
    VecEnv envs(toy::make_envs(4, discrete), setup.seed);
    auto algo = make_algorithm(setup, envs.spec());
    CHECK(algo->name() == "trpo");
    const auto metrics = checks::train(*algo, envs, discrete ? 6000 : 12000, 12000);
    int accepted = 0;
    for (const auto& m : metrics) {
      CHECK(m[1].first == "kl_divergence");
      CHECK(m[1].second <= setup.trpo.target_kl);
      if (m[2].second == 1.0) {
        ++accepted;
        CHECK(m[0].second > 0.0);  // an accepted step improves the surrogate
      }
    }
    CHECK(accepted > static_cast<int>(metrics.size()) / 2);
    const double mean_return = envs.episodes().stats().mean_return;
    INFO((discrete ? "discrete" : "continuous") << ": mean return " << mean_return << " (random about 5 / 3.5, best 10)");
    CHECK(mean_return > (discrete ? 9.0 : 8.0));
  }
}

TEST_CASE("TRPO: same seed, same run, checkpoints resume exactly, models round-trip", "[trpo][checkpoint]") {
  const Setup setup = trpo_setup(2);
  checks::same_seed_same_run(setup, checks::sign_envs(2, false), 512);
  checks::resume_is_exact(setup, checks::sign_envs(2, true), 256, 768, 1024);
  VecEnv envs(toy::make_envs(2, false), 2);
  auto algo = make_algorithm(setup, envs.spec());
  checks::train(*algo, envs, 256, 256);
  checks::model_round_trips(setup, *algo, envs.spec(), toy::random_observation);
}

TEST_CASE("TRPO refuses a shared trunk", "[trpo]") {
  Setup setup = trpo_setup(0);
  setup.network.shared = true;
  CHECK_THROWS_WITH(make_algorithm(setup, toy::SignEnv().spec()),
                    Catch::Contains("sign_trpo.json") && Catch::Contains("network.shared"));
}
