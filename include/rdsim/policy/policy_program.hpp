#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/nn/activation.hpp"

// A trained policy's deterministic action as a plain sequence of array operations on a batch of
// encoded observations (one per column): what `rdsim export` writes as an ONNX graph (src/export/)
// and what run_policy_program() computes here, so that a test can hold the program against the
// algorithm's own act(). Each algorithm that can be exported builds it from its weights
// (Algorithm::policy_program).
namespace rdsim {

namespace nn {
class Mlp;      // rdsim/nn/mlp.hpp
class Cnn;      // rdsim/nn/cnn.hpp
struct Conv2d;  // rdsim/nn/conv.hpp
}  // namespace nn

struct PolicyOp {
  enum class Kind {
    Standardize,  // clip((x - a) * b, -scalar, scalar): normalize_observations (a: mean, b: 1 / std)
    Scale,        // x * scalar: network.input_scale
    Dense,        // weight * x + a
    Activate,     // activation, elementwise
    KeepRows,     // the first `rows` rows (SAC's means, before its log stds)
    Clip,         // min(max(x, a), b): a Gaussian policy's mean to the Box
    Rescale,      // min(a + (clip(x, -1, 1) + 1) * (b - a) / 2, b): [-1, 1] to the Box (off-policy actors)
    ArgMax,       // the row of the largest value (discrete actions; the first of equals)
    Conv,         // conv's convolution (images flattened height x width x channels, as nn::Conv2d keeps them)
  };
  Kind kind = Kind::Scale;
  Eigen::MatrixXf weight;
  Eigen::VectorXf a, b;
  float scalar = 1.0f;
  nn::Activation activation = nn::Activation::Identity;
  int rows = 0;
  std::shared_ptr<const nn::Conv2d> conv;
};

struct PolicyProgram {
  std::string algorithm;  // "ppo", "sac", ...
  int input_size = 0;     // encoded observation size
  // Pixel observations: uint8 images of `image_shape` (height, width, channels), which the program
  // takes encoded (scaled to [0, 1] and flattened, as rdsim's networks do).
  bool pixels = false;
  std::vector<int> image_shape;
  bool discrete = false;  // the output: one action index per observation (else `action_size` values)
  int action_size = 0;
  std::vector<PolicyOp> ops;

  void standardize(const Eigen::VectorXf& mean, const Eigen::VectorXf& inverse_std, float clip);
  void scale(float factor);  // nothing for 1
  // The Mlp's layers: activation after each hidden one, and after the last one too when `activate_output`.
  void mlp(const nn::Mlp& net, bool activate_output = false);
  // The Cnn's conv layers (each followed by its activation), then its dense head as mlp() adds it.
  void cnn(const nn::Cnn& net);
  void activate(nn::Activation activation);  // nothing for Identity
  void keep_rows(int rows);
  void clip(const Eigen::VectorXf& low, const Eigen::VectorXf& high);
  void rescale(const Eigen::VectorXf& low, const Eigen::VectorXf& high);
  void argmax();
};

// The program's actions for observations x (input_size x n): action_size x n values, or for a
// discrete policy 1 x n indices (as floats).
Eigen::MatrixXf run_policy_program(const PolicyProgram& program, const Eigen::MatrixXf& x);

}  // namespace rdsim
