#include "rdsim/envs/classic/cartpole.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"

namespace rdsim {
namespace {

// The whole mutable state, copied as bytes by save_state().
struct Snapshot {
  double x, x_dot, theta, theta_dot;
  int steps;
  bool done;
};

}  // namespace

EnvConfig cartpole_defaults() {
  EnvConfig c;
  c.name = "cartpole";
  c.max_steps = 500;  // CartPole-v1
  return c;
}

CartPole::CartPole(const EnvConfig& config) {
  if (config.observation != ObservationMode::GroundTruth) {
    throw Error("env.observation: cartpole only offers \"ground_truth\" observations");
  }
  if (!config.is_discrete) throw Error("env.is_discrete: cartpole only has a discrete action space");
  spec_.env_name = "cartpole";
  spec_.observation.type = ObsType::Float32;
  spec_.observation.shape = {4};
  const float big = std::numeric_limits<float>::max();
  spec_.observation.high.resize(4);
  spec_.observation.high << static_cast<float>(2 * x_threshold), big, static_cast<float>(2 * theta_threshold), big;
  spec_.observation.low = -spec_.observation.high;
  spec_.observation.parts = {{"cart_position", 1}, {"cart_velocity", 1}, {"pole_angle", 1}, {"pole_angular_velocity", 1}};
  spec_.action.discrete = true;
  spec_.action.n = 2;
  spec_.max_episode_steps = config.max_steps;
  spec_.control_dt = tau;
}

void CartPole::observe(float* out) const {
  out[0] = static_cast<float>(x_);
  out[1] = static_cast<float>(x_dot_);
  out[2] = static_cast<float>(theta_);
  out[3] = static_cast<float>(theta_dot_);
}

// The plain interface through the "into" one: one implementation of the dynamics.
Observation CartPole::reset(std::optional<std::uint64_t> seed) { return reset_through_into(*this, seed); }

StepResult CartPole::step(const Action& action) { return step_through_into(*this, action); }

void CartPole::reset_into(ObservationOut out, std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  x_ = rng_.uniform(-0.05, 0.05);
  x_dot_ = rng_.uniform(-0.05, 0.05);
  theta_ = rng_.uniform(-0.05, 0.05);
  theta_dot_ = rng_.uniform(-0.05, 0.05);
  steps_ = 0;
  done_ = false;
  observe(out.values);
}

StepOutcome CartPole::step_into(const Action& action, ObservationOut out) {
  if (action.index != 0 && action.index != 1) {
    throw Error("cartpole: action must be 0 (push left) or 1 (push right), got " + std::to_string(action.index));
  }
  StepOutcome r;
  if (done_) {
    // Stepping a finished episode (Gym warns): nothing moves, no reward.
    observe(out.values);
    r.terminated = true;
    return r;
  }
  const double total_mass = cart_mass + pole_mass;
  const double pole_mass_length = pole_mass * half_length;
  const double force = action.index == 1 ? force_mag : -force_mag;
  const double cos_theta = std::cos(theta_), sin_theta = std::sin(theta_);
  const double temp = (force + pole_mass_length * theta_dot_ * theta_dot_ * sin_theta) / total_mass;
  const double theta_acc = (gravity * sin_theta - cos_theta * temp) /
                           (half_length * (4.0 / 3.0 - pole_mass * cos_theta * cos_theta / total_mass));
  const double x_acc = temp - pole_mass_length * theta_acc * cos_theta / total_mass;
  // Explicit Euler in Gym's order: positions advance with the old velocities.
  x_ += tau * x_dot_;
  x_dot_ += tau * x_acc;
  theta_ += tau * theta_dot_;
  theta_dot_ += tau * theta_acc;
  ++steps_;

  observe(out.values);
  r.reward = 1.0f;
  r.terminated = x_ < -x_threshold || x_ > x_threshold || theta_ < -theta_threshold || theta_ > theta_threshold;
  r.truncated = steps_ >= spec_.max_episode_steps;
  r.info.success = r.truncated && !r.terminated;
  r.info.out_of_bounds = x_ < -x_threshold || x_ > x_threshold;
  r.info.distance = static_cast<float>(std::abs(theta_));
  done_ = r.terminated || r.truncated;
  return r;
}

std::string CartPole::save_state() const {
  Snapshot s;
  std::memset(&s, 0, sizeof s);  // padding too: identical states give identical bytes
  // Member by member: assigning a whole Snapshot may copy a temporary's undefined padding.
  s.x = x_;
  s.x_dot = x_dot_;
  s.theta = theta_;
  s.theta_dot = theta_dot_;
  s.steps = steps_;
  s.done = done_;
  std::string bytes(sizeof(Snapshot), '\0');
  std::memcpy(bytes.data(), &s, sizeof(Snapshot));
  return bytes + rng_to_bytes(rng_);
}

void CartPole::load_state(const std::string& bytes, const std::string& source) {
  if (bytes.size() != sizeof(Snapshot) + sizeof(Rng)) throw Error(source + ": not a cartpole state");
  Snapshot s;
  std::memcpy(&s, bytes.data(), sizeof(Snapshot));
  unsigned char done_byte = 0;
  std::memcpy(&done_byte, bytes.data() + offsetof(Snapshot, done), 1);
  if (!std::isfinite(s.x) || !std::isfinite(s.x_dot) || !std::isfinite(s.theta) || !std::isfinite(s.theta_dot) ||
      s.steps < 0 || s.steps > spec_.max_episode_steps || done_byte > 1)
    throw Error(source + ": cartpole state is damaged (values out of range)");
  rng_ = rng_from_bytes(bytes.substr(sizeof(Snapshot)), source);
  x_ = s.x;
  x_dot_ = s.x_dot;
  theta_ = s.theta;
  theta_dot_ = s.theta_dot;
  steps_ = s.steps;
  done_ = s.done;
}

std::unique_ptr<Env> make_cartpole(const EnvConfig& config) { return std::make_unique<CartPole>(config); }

}  // namespace rdsim
