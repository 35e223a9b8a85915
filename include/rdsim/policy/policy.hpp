#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/model_envelope.hpp"
#include "rdsim/policy/policy_program.hpp"

// A trained policy loaded from a model.bin (or checkpoint.bin) that `rdsim train` wrote, without
// rdsim's simulation, rendering or training code: what a robot's controller links (the library
// rdsim_policy; examples/policy/ shows it in 30 lines). It gives the deterministic action, the one
// `rdsim replay` takes, computed from the policy part of the file (core/model_envelope.hpp).
namespace rdsim {

class Policy {
public:
  // rdsim::Error naming `path` for a file that is not a complete rdsim model, one written before
  // model format 4 (it has no policy part), a model of an algorithm without a policy (random), or
  // a damaged policy.
  static Policy load(const std::string& path);
  // The same from a model file's bytes; `source` names them in errors.
  static Policy from_bytes(std::string_view bytes, const std::string& source);

  const std::string& algorithm() const { return program_.algorithm; }
  // The env the policy was trained on: "jaka_button: observation float32 {9}, actions discrete 6".
  const std::string& env_spec() const { return spec_; }
  // What an observation is: float32 values of this shape, or a uint8 image (height, width, channels).
  const ObservationSpace& observation_space() const { return space_; }
  bool discrete() const { return program_.discrete; }
  int action_size() const { return program_.action_size; }  // 1 for a discrete policy

  // The action for one observation, as the env gives it (flat float32 values, or the HWC image):
  // a discrete policy's index in Action::index, a continuous one's values in Action::values.
  // rdsim::Error when the observation has the wrong size or type.
  Action act(const Observation& observation) const;
  Action act(std::span<const float> observation) const;
  Action act(std::span<const std::uint8_t> image) const;
  // Actions for network inputs, one observation per column (observation_input.hpp: images scaled
  // to [0, 1]): action_size x n values, or 1 x n indices (as floats) for a discrete policy.
  Eigen::MatrixXf act_batch(const Eigen::MatrixXf& inputs) const;

  const PolicyProgram& program() const { return program_; }

private:
  Policy(PolicyProgram program, std::string spec);
  // The policy part of a decoded model file; the errors load() describes, naming `source`.
  static Policy from_envelope(ModelEnvelope&& envelope, const std::string& source);
  Action action(const Eigen::MatrixXf& y) const;

  PolicyProgram program_;
  std::string spec_;
  ObservationSpace space_;
};

}  // namespace rdsim
