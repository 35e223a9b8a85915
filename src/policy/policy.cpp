#include "rdsim/policy/policy.hpp"

#include <utility>

#include "rdsim/core/error.hpp"
#include "rdsim/core/model_envelope.hpp"
#include "rdsim/core/observation_input.hpp"
#include "rdsim/policy/policy_file.hpp"

namespace rdsim {

Policy Policy::load(const std::string& path) { return from_envelope(read_model_envelope(path), path); }

Policy Policy::from_bytes(std::string_view bytes, const std::string& source) {
  return from_envelope(decode_model_envelope(bytes, source), source);
}

Policy Policy::from_envelope(ModelEnvelope&& e, const std::string& source) {
  if (e.version < 4)
    throw Error(source + ": has no policy part (written by an rdsim whose model files had none, format version " +
                std::to_string(e.version) + "); train it again, or load it with `rdsim replay` or Python's rdsim.load_model");
  if (e.policy.empty())
    throw Error(source + ": has no policy part: its algorithm has no policy to run (a random agent's model holds no weights)");
  return Policy(decode_policy_program(e.policy, source), std::move(e.spec));
}

Policy::Policy(PolicyProgram program, std::string spec) : program_(std::move(program)), spec_(std::move(spec)) {
  if (program_.pixels) {
    space_.type = ObsType::UInt8;
    space_.shape = program_.image_shape;
  } else {
    space_.type = ObsType::Float32;
    space_.shape = {program_.input_size};
  }
}

Eigen::MatrixXf Policy::act_batch(const Eigen::MatrixXf& inputs) const {
  if (inputs.rows() != program_.input_size)
    throw Error("rdsim::Policy: observations have " + std::to_string(inputs.rows()) + " values each, the policy takes " +
                std::to_string(program_.input_size));
  return run_policy_program(program_, inputs);
}

Action Policy::action(const Eigen::MatrixXf& y) const {
  if (program_.discrete) return Action::discrete(static_cast<int>(y(0, 0)));
  return Action::continuous(y.col(0));
}

Action Policy::act(const Observation& observation) const {
  Eigen::MatrixXf x(program_.input_size, 1);
  encode_observation(observation, space_, x.col(0));
  return action(run_policy_program(program_, x));
}

Action Policy::act(std::span<const float> observation) const {
  if (program_.pixels) throw Error("rdsim::Policy: the policy takes uint8 images, not float values");
  Observation o;
  o.values = Eigen::Map<const Eigen::VectorXf>(observation.data(), static_cast<Eigen::Index>(observation.size()));
  return act(o);
}

Action Policy::act(std::span<const std::uint8_t> image) const {
  if (!program_.pixels) throw Error("rdsim::Policy: the policy takes float values, not uint8 images");
  Observation o;
  o.pixels.assign(image.begin(), image.end());
  return act(o);
}

}  // namespace rdsim
