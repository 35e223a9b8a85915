#include <catch2/catch.hpp>

#include "rdsim/algorithms/actor_critic.hpp"
#include "toy_env.hpp"

namespace {

// L = sum_j a_j log p_j + b_j H_j + c_j V_j, the form every actor-critic loss takes.
double loss(rdsim::ActorCritic& ac, const Eigen::MatrixXf& obs, const Eigen::MatrixXf& actions,
            const Eigen::VectorXf& a, const Eigen::VectorXf& b, const Eigen::VectorXf& c) {
  const auto& ev = ac.evaluate(obs, actions);
  return a.cast<double>().dot(ev.log_probs.cast<double>()) + b.cast<double>().dot(ev.entropy.cast<double>()) +
         c.cast<double>().dot(ev.values.cast<double>());
}

void check_gradients(bool discrete, bool shared) {
  toy::SignEnv env(discrete);
  rdsim::NetworkConfig net;
  net.hidden_sizes = {5, 4};
  net.shared = shared;
  net.log_std_init = -0.3;
  rdsim::Rng rng(123);
  rdsim::ActorCritic ac(env.spec(), net, rng);
  // Larger output weights than the 0.01-gain init, so the policy term is not negligible.
  for (auto& p : ac.params()) *p.value *= 3.0f;

  const int batch = 6;
  Eigen::MatrixXf obs(2, batch), actions(1, batch);
  Eigen::VectorXf a(batch), b(batch), c(batch);
  for (int j = 0; j < batch; ++j) {
    obs(0, j) = static_cast<float>(rng.uniform(-1, 1));
    obs(1, j) = static_cast<float>(rng.uniform(0, 1));
    actions(0, j) = discrete ? static_cast<float>(rng.below(2)) : static_cast<float>(rng.normal());
    a[j] = static_cast<float>(rng.normal());
    b[j] = static_cast<float>(rng.normal());
    c[j] = static_cast<float>(rng.normal());
  }
  ac.zero_grad();
  loss(ac, obs, actions, a, b, c);
  ac.backward(a, b, c);
  int checked = 0;
  for (const auto& p : ac.params()) {
    const Eigen::MatrixXf analytic = *p.grad;
    for (Eigen::Index k = 0; k < p.value->size(); ++k) {
      const float keep = p.value->data()[k];
      const float eps = 1e-2f;
      p.value->data()[k] = keep + eps;
      const double up = loss(ac, obs, actions, a, b, c);
      p.value->data()[k] = keep - eps;
      const double down = loss(ac, obs, actions, a, b, c);
      p.value->data()[k] = keep;
      const double numeric = (up - down) / (2.0 * eps);
      INFO(p.name << "[" << k << "] analytic " << analytic.data()[k] << " numeric " << numeric);
      CHECK(std::abs(numeric - analytic.data()[k]) <= 2e-3 + 2e-2 * std::abs(numeric));
      ++checked;
    }
  }
  CHECK(checked > 40);
}

}  // namespace

TEST_CASE("actor-critic gradients match finite differences", "[actor_critic]") {
  SECTION("discrete, separate networks") { check_gradients(true, false); }
  SECTION("discrete, shared trunk") { check_gradients(true, true); }
  SECTION("continuous, separate networks") { check_gradients(false, false); }
  SECTION("continuous, shared trunk") { check_gradients(false, true); }
}

TEST_CASE("actor-critic acting: modes, log-probs and action clipping", "[actor_critic]") {
  toy::SignEnv env(false);
  rdsim::NetworkConfig net;
  rdsim::Rng init(5), rng(6);
  rdsim::ActorCritic ac(env.spec(), net, init);
  Eigen::MatrixXf obs = Eigen::MatrixXf::Random(2, 4);
  rdsim::ActBatch mode, sampled;
  ac.act(obs, true, rng, mode);
  ac.act(obs, false, rng, sampled);
  const auto& ev = ac.evaluate(obs, sampled.actions);
  for (int j = 0; j < 4; ++j) CHECK(ev.log_probs[j] == Approx(sampled.log_probs[j]).margin(1e-5));
  CHECK(ev.values.isApprox(mode.values));
  CHECK((mode.actions - sampled.actions).cwiseAbs().maxCoeff() > 0.0f);
  // Samples outside the Box are clipped for the env, not for the log-prob.
  CHECK(ac.env_action(Eigen::VectorXf::Constant(1, 3.0f)).values[0] == 1.0f);
  CHECK(ac.env_action(Eigen::VectorXf::Constant(1, -3.0f)).values[0] == -1.0f);
}

TEST_CASE("network.input_scale: the networks see the observations times the scale", "[actor_critic]") {
  for (bool shared : {false, true}) {
    toy::SignEnv env(true);
    rdsim::NetworkConfig plain, scaled;
    plain.shared = scaled.shared = shared;
    scaled.input_scale = 10.0;
    rdsim::Rng init_a(7), init_b(7), rng(8);
    rdsim::ActorCritic a(env.spec(), plain, init_a), b(env.spec(), scaled, init_b);
    const Eigen::MatrixXf obs = Eigen::MatrixXf::Random(2, 5) * 0.1f;
    const Eigen::MatrixXf actions = Eigen::MatrixXf::Zero(1, 5);
    rdsim::ActBatch out_a, out_b;
    a.act(obs * 10.0f, true, rng, out_a);
    b.act(obs, true, rng, out_b);
    INFO("shared " << shared);
    CHECK(out_a.actions == out_b.actions);
    CHECK(out_a.values.isApprox(out_b.values, 1e-5f));
    CHECK(a.predict_values(obs * 10.0f).isApprox(b.predict_values(obs), 1e-5f));
    const Eigen::VectorXf log_probs = a.evaluate(obs * 10.0f, actions).log_probs;
    CHECK(log_probs.isApprox(b.evaluate(obs, actions).log_probs, 1e-5f));
  }
  // Pixels are already in [0, 1]: a scale there is a config mistake.
  rdsim::Spec pixels = toy::SignEnv(true).spec();
  pixels.observation.type = rdsim::ObsType::UInt8;
  pixels.observation.shape = {16, 16, 1};
  rdsim::NetworkConfig scaled;
  scaled.input_scale = 2.0;
  rdsim::Rng init(1);
  CHECK_THROWS_WITH(rdsim::ActorCritic(pixels, scaled, init), Catch::Contains("network.input_scale"));
}
