#pragma once
// A tiny env for algorithm tests (the algorithms suite does not link the real envs).
// Observation (s, t / length) with s = +-1 drawn per step; discrete: reward 1 when the action is
// 1 for s > 0 and 0 for s < 0; continuous: reward 1 - (a - 0.5 s)^2 with a in [-1, 1].
// Episodes are truncated after `length` steps, or terminated at step `terminate_at` (> 0).
#include <algorithm>
#include <cstring>
#include <optional>
#include <sstream>
#include <initializer_list>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/rng_bytes.hpp"

namespace toy {

// A dynamic-size vector from values (fixed-size temporaries assigned to VectorXf trip GCC 12's
// -Warray-bounds in Eigen's SSE copies).
inline Eigen::VectorXf vec(std::initializer_list<float> values) {
  Eigen::VectorXf v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (float x : values) v[i++] = x;
  return v;
}

class SignEnv final : public rdsim::Env, public rdsim::EnvState {
public:
  explicit SignEnv(bool discrete = true, int length = 10, int terminate_at = 0)
      : length_(length), terminate_at_(terminate_at) {
    spec_.env_name = "sign";
    spec_.observation.shape = {2};
    spec_.observation.low.resize(2);
    spec_.observation.low << -1.0f, 0.0f;
    spec_.observation.high = Eigen::VectorXf::Ones(2);
    spec_.action.discrete = discrete;
    if (discrete) {
      spec_.action.n = 2;
    } else {
      spec_.action.low = Eigen::VectorXf::Constant(1, -1.0f);
      spec_.action.high = Eigen::VectorXf::Constant(1, 1.0f);
    }
    spec_.max_episode_steps = length;
  }

  const rdsim::Spec& spec() const override { return spec_; }
  // Whether VecEnv may step it on another worker's thread (its default: no).
  bool any_thread = false;
  bool steps_on_any_thread() const override { return any_thread; }

  rdsim::Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override {
    if (seed) rng_.reseed(*seed);
    t_ = 0;
    draw();
    return observe();
  }

  rdsim::StepResult step(const rdsim::Action& action) override {
    rdsim::StepResult r;
    if (spec_.action.discrete) {
      r.reward = (action.index == 1) == (sign_ > 0) ? 1.0f : 0.0f;
    } else {
      const float d = action.values[0] - 0.5f * sign_;
      r.reward = 1.0f - d * d;
    }
    ++t_;
    r.terminated = terminate_at_ > 0 && t_ == terminate_at_;
    r.truncated = !r.terminated && t_ >= length_;
    r.info.success = r.truncated;
    draw();
    r.observation = observe();
    return r;
  }

  std::string save_state() const override {
    std::string s = rdsim::rng_to_bytes(rng_);
    s.append(reinterpret_cast<const char*>(&t_), sizeof t_);
    s.append(reinterpret_cast<const char*>(&sign_), sizeof sign_);
    return s;
  }
  void load_state(const std::string& bytes, const std::string& source) override {
    if (bytes.size() != sizeof(rdsim::Rng) + sizeof t_ + sizeof sign_) throw rdsim::Error(source + ": bad state");
    rng_ = rdsim::rng_from_bytes(bytes.substr(0, sizeof(rdsim::Rng)), source);
    std::memcpy(&t_, bytes.data() + sizeof(rdsim::Rng), sizeof t_);
    std::memcpy(&sign_, bytes.data() + sizeof(rdsim::Rng) + sizeof t_, sizeof sign_);
  }

private:
  void draw() { sign_ = rng_.uniform() < 0.5 ? -1.0f : 1.0f; }
  rdsim::Observation observe() const {
    rdsim::Observation o;
    o.values.resize(2);
    o.values << sign_, static_cast<float>(t_) / static_cast<float>(length_);
    return o;
  }

  rdsim::Spec spec_;
  rdsim::Rng rng_;
  int length_, terminate_at_;
  int t_ = 0;
  float sign_ = 1.0f;
};

// The observation (s, t / length) of SignEnv.
inline rdsim::Observation observation(float s, float time = 0.5f) {
  rdsim::Observation o;
  o.values = vec({s, time});
  return o;
}
// A random one: s = +-1, time in [0, 1).
inline rdsim::Observation random_observation(rdsim::Rng& rng) {
  return observation(rng.uniform() < 0.5 ? -1.0f : 1.0f, static_cast<float>(rng.uniform()));
}

inline std::vector<std::unique_ptr<rdsim::Env>> make_envs(int n, bool discrete = true, int length = 10,
                                                          int terminate_at = 0) {
  std::vector<std::unique_ptr<rdsim::Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<SignEnv>(discrete, length, terminate_at));
  return envs;
}

// A corridor of 6 cells; action 1 moves right, 0 left. Reaching the right end gives +1 and
// terminates; each step costs 0.01; 30 steps truncate. Optimal: always right. Observations:
// one-hot cells, or (pixels) an 8x6 RGB image with the agent's column lit.
class Corridor final : public rdsim::Env, public rdsim::EnvState {
public:
  explicit Corridor(bool pixels = false) : pixels_(pixels) {
    spec_.env_name = pixels ? "pixel_corridor" : "corridor";
    if (pixels) {
      spec_.observation.type = rdsim::ObsType::UInt8;
      spec_.observation.shape = {kRows, kCells, 3};
    } else {
      spec_.observation.shape = {kCells};
      spec_.observation.low = Eigen::VectorXf::Zero(kCells);
      spec_.observation.high = Eigen::VectorXf::Ones(kCells);
    }
    spec_.action.discrete = true;
    spec_.action.n = 2;
    spec_.max_episode_steps = 30;
  }
  const rdsim::Spec& spec() const override { return spec_; }
  rdsim::Observation reset(std::optional<std::uint64_t>) override {
    pos_ = 0;
    steps_ = 0;
    return observe();
  }
  rdsim::StepResult step(const rdsim::Action& a) override {
    pos_ = std::clamp(pos_ + (a.index == 1 ? 1 : -1), 0, kCells - 1);
    ++steps_;
    rdsim::StepResult r;
    r.terminated = pos_ == kCells - 1;
    r.truncated = !r.terminated && steps_ >= spec_.max_episode_steps;
    r.reward = r.terminated ? 1.0f : -0.01f;
    r.info.success = r.terminated;
    r.observation = observe();
    return r;
  }
  std::string save_state() const override { return std::to_string(pos_) + " " + std::to_string(steps_); }
  void load_state(const std::string& bytes, const std::string&) override {
    std::istringstream in(bytes);
    in >> pos_ >> steps_;
  }

private:
  static constexpr int kCells = 6, kRows = 8;
  rdsim::Observation observe() const {
    rdsim::Observation o;
    if (!pixels_) {
      o.values = Eigen::VectorXf::Zero(kCells);
      o.values[pos_] = 1.0f;
      return o;
    }
    o.pixels.assign(kRows * kCells * 3, 20);
    for (int y = 0; y < kRows; ++y)
      for (int c = 0; c < 3; ++c) o.pixels[static_cast<std::size_t>((y * kCells + pos_) * 3 + c)] = 240;
    return o;
  }
  bool pixels_;
  rdsim::Spec spec_;
  int pos_ = 0, steps_ = 0;
};

}  // namespace toy
