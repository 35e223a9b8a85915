#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"

// The classic cart-pole balancing task (Barto, Sutton & Anderson 1983) with Gym CartPole-v1's
// constants and limits: observation (x, x_dot, theta, theta_dot), Discrete(2) push left/right
// with 10 N, Euler integration at 0.02 s, +1 reward per step (including the failing one),
// terminated when |x| > 2.4 m or |theta| > 12 degrees, truncated after 500 steps
// (env option max_steps). StepInfo::success: the episode reached the step limit
// without failing. Needs no physics engine: the quickest env to check that learning works.
namespace rdsim {

class CartPole final : public Env, public EnvState {
public:
  explicit CartPole(const EnvConfig& config);

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;
  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed = std::nullopt) override;
  StepOutcome step_into(const Action& action, ObservationOut out) override;

  std::string save_state() const override;
  void load_state(const std::string& bytes, const std::string& source) override;

  // Gym's constants.
  static constexpr double gravity = 9.8;
  static constexpr double cart_mass = 1.0;
  static constexpr double pole_mass = 0.1;
  static constexpr double half_length = 0.5;
  static constexpr double force_mag = 10.0;
  static constexpr double tau = 0.02;
  static constexpr double x_threshold = 2.4;
  static constexpr double theta_threshold = 12.0 * 2.0 * 3.14159265358979323846 / 360.0;

private:
  void observe(float* out) const;

  Spec spec_;
  Rng rng_;
  double x_ = 0, x_dot_ = 0, theta_ = 0, theta_dot_ = 0;
  int steps_ = 0;
  bool done_ = true;
};

EnvConfig cartpole_defaults();  // max_steps 500
std::unique_ptr<Env> make_cartpole(const EnvConfig& config);

}  // namespace rdsim
