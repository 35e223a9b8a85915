#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"

// The inverted pendulum swing-up with Gymnasium Pendulum-v1's dynamics, reward and limits, to
// validate the continuous-action algorithms (SAC, TD3, DDPG) against published budgets.
//
// State: angle theta (rad, 0 = upright) and angular velocity theta_dot (rad/s). Observation
// (cos theta, sin theta, theta_dot), bounds (-1, -1, -8)..(1, 1, 8). Action: Box(1), the torque
// u in [-2, 2] N m (clipped). One step (dt = 0.05 s, g = 10, m = 1, l = 1), semi-implicit Euler:
//   theta_dot' = clip(theta_dot + (3 g / (2 l) sin theta + 3 / (m l^2) u) dt, -8, 8)
//   theta'     = theta + theta_dot' dt
// Reward: -(normalize(theta)^2 + 0.1 theta_dot^2 + 0.001 u^2), from the state BEFORE the step,
// normalize(x) = ((x + pi) mod 2 pi) - pi; between -16.27 and 0 per step. Never terminates;
// truncated after max_steps (default 200, Gymnasium's TimeLimit). Reset: theta ~ U(-pi, pi),
// theta_dot ~ U(-1, 1). StepInfo::distance is |normalize(theta)|; success is not defined.
namespace rdsim {

class Pendulum final : public Env, public EnvState {
public:
  explicit Pendulum(const EnvConfig& config);

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;

  std::string save_state() const override;
  void load_state(const std::string& bytes, const std::string& source) override;

  // Gymnasium's constants.
  static constexpr double max_speed = 8.0;
  static constexpr double max_torque = 2.0;
  static constexpr double dt = 0.05;
  static constexpr double g = 10.0;
  static constexpr double m = 1.0;
  static constexpr double l = 1.0;

  // ((x + pi) mod 2 pi) - pi with a floored modulo, as Python's %: in [-pi, pi).
  static double normalize_angle(double x);

  // For tests: put the pendulum in a given state.
  void set_state(double theta, double theta_dot);

private:
  Observation observe() const;

  Spec spec_;
  Rng rng_;
  double theta_ = 0, theta_dot_ = 0;
  int steps_ = 0;
};

EnvConfig pendulum_defaults();  // max_steps 200, is_discrete false
std::unique_ptr<Env> make_pendulum(const EnvConfig& config);

}  // namespace rdsim
