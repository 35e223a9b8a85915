#include "rdsim/envs/classic/pendulum.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"

namespace rdsim {
namespace {

// The whole mutable state, copied as bytes by save_state().
struct Snapshot {
  double theta, theta_dot;
  int steps;
};

constexpr double kPi = std::numbers::pi;

}  // namespace

EnvConfig pendulum_defaults() {
  EnvConfig c;
  c.name = "pendulum";
  c.is_discrete = false;
  c.max_steps = 200;  // Pendulum-v1's TimeLimit
  return c;
}

Pendulum::Pendulum(const EnvConfig& config) {
  if (config.observation != ObservationMode::GroundTruth)
    throw Error("env.observation: pendulum only offers \"ground_truth\" observations");
  if (config.is_discrete) throw Error("env.is_discrete: pendulum only has a continuous action space (expected false)");
  spec_.env_name = "pendulum";
  spec_.observation.type = ObsType::Float32;
  spec_.observation.shape = {3};
  spec_.observation.high = (Eigen::VectorXf(3) << 1.0f, 1.0f, static_cast<float>(max_speed)).finished();
  spec_.observation.low = -spec_.observation.high;
  spec_.observation.parts = {{"cos_angle", 1}, {"sin_angle", 1}, {"angular_velocity", 1}};
  spec_.action.discrete = false;
  spec_.action.low = Eigen::VectorXf::Constant(1, static_cast<float>(-max_torque));
  spec_.action.high = Eigen::VectorXf::Constant(1, static_cast<float>(max_torque));
  spec_.max_episode_steps = config.max_steps;
  spec_.control_dt = dt;
}

double Pendulum::normalize_angle(double x) {
  const double period = 2.0 * kPi;
  const double shifted = x + kPi;
  return shifted - period * std::floor(shifted / period) - kPi;
}

void Pendulum::set_state(double theta, double theta_dot) {
  theta_ = theta;
  theta_dot_ = theta_dot;
}

Observation Pendulum::observe() const {
  Observation obs;
  obs.values.resize(3);
  obs.values << static_cast<float>(std::cos(theta_)), static_cast<float>(std::sin(theta_)),
      static_cast<float>(theta_dot_);
  return obs;
}

Observation Pendulum::reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  theta_ = rng_.uniform(-kPi, kPi);
  theta_dot_ = rng_.uniform(-1.0, 1.0);
  steps_ = 0;
  return observe();
}

StepResult Pendulum::step(const Action& action) {
  if (action.values.size() != 1 || !std::isfinite(action.values[0]))
    throw Error("pendulum: expected one finite torque value, got " + std::to_string(action.values.size()) + " values");
  StepResult r;
  if (steps_ >= spec_.max_episode_steps) {
    // Stepping a finished episode (it only ends by truncation): nothing moves, no reward.
    r.observation = observe();
    r.terminated = true;
    return r;
  }
  const double u = std::clamp(static_cast<double>(action.values[0]), -max_torque, max_torque);
  const double angle = normalize_angle(theta_);
  const double cost = angle * angle + 0.1 * theta_dot_ * theta_dot_ + 0.001 * u * u;
  // Gymnasium's order: the new velocity (clipped) moves the angle.
  double new_theta_dot = theta_dot_ + (3.0 * g / (2.0 * l) * std::sin(theta_) + 3.0 / (m * l * l) * u) * dt;
  new_theta_dot = std::clamp(new_theta_dot, -max_speed, max_speed);
  theta_ += new_theta_dot * dt;
  theta_dot_ = new_theta_dot;
  ++steps_;

  r.observation = observe();
  r.reward = static_cast<float>(-cost);
  r.terminated = false;
  r.truncated = steps_ >= spec_.max_episode_steps;
  r.info.distance = static_cast<float>(std::abs(normalize_angle(theta_)));
  return r;
}

std::string Pendulum::save_state() const {
  Snapshot s;
  std::memset(&s, 0, sizeof s);  // padding too: identical states give identical bytes
  s.theta = theta_;
  s.theta_dot = theta_dot_;
  s.steps = steps_;
  std::string bytes(sizeof(Snapshot), '\0');
  std::memcpy(bytes.data(), &s, sizeof(Snapshot));
  return bytes + rng_to_bytes(rng_);
}

void Pendulum::load_state(const std::string& bytes, const std::string& source) {
  if (bytes.size() != sizeof(Snapshot) + sizeof(Rng)) throw Error(source + ": not a pendulum state");
  Snapshot s;
  std::memcpy(&s, bytes.data(), sizeof(Snapshot));
  if (!std::isfinite(s.theta) || !std::isfinite(s.theta_dot) || s.steps < 0 || s.steps > spec_.max_episode_steps)
    throw Error(source + ": pendulum state is damaged (values out of range)");
  rng_ = rng_from_bytes(bytes.substr(sizeof(Snapshot)), source);
  theta_ = s.theta;
  theta_dot_ = s.theta_dot;
  steps_ = s.steps;
}

std::unique_ptr<Env> make_pendulum(const EnvConfig& config) { return std::make_unique<Pendulum>(config); }

}  // namespace rdsim
