#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "rdsim/core/rng.hpp"
#include "rdsim/nn/activation.hpp"
#include "rdsim/nn/param.hpp"

// Multi-layer perceptrons on batches stored one column per sample (features x batch).
namespace rdsim::nn {

// y = W x + b for a batch x (in x batch) -> (out x batch).
struct Dense {
  Tensor weight;  // out x in
  Tensor bias;    // out x 1

  Dense() = default;
  // Orthogonal weights scaled by `gain`, zero bias.
  Dense(int in, int out, float gain, Rng& rng);

  int in_size() const { return static_cast<int>(weight.value.cols()); }
  int out_size() const { return static_cast<int>(weight.value.rows()); }
};

struct MlpShape {
  int input_size = 0;
  std::vector<int> hidden_sizes;   // may be empty (a linear model)
  int output_size = 0;
  Activation activation = Activation::Tanh;  // after every hidden layer; the output is linear
};

class Mlp {
public:
  Mlp() = default;
  // Hidden layers: orthogonal init with `hidden_gain`; output layer with `output_gain`
  // (baselines: sqrt(2) hidden, 0.01 policy head, 1 value head). Biases start at zero.
  // Throws rdsim::Error on non-positive sizes.
  Mlp(const MlpShape& shape, float output_gain, Rng& rng, float hidden_gain = 1.41421356f);

  // Training forward pass on (input_size x batch); caches the activations backward() needs.
  // The returned reference stays valid until the next forward().
  const Eigen::MatrixXf& forward(const Eigen::MatrixXf& x);

  // Back-propagates dLoss/dOutput (output_size x batch) of the LAST forward() batch.
  // ACCUMULATES (+=) into the parameter gradients, so several losses can share a network.
  // Returns dLoss/dInput (input_size x batch), or an empty matrix when !need_input_grad.
  Eigen::MatrixXf backward(const Eigen::MatrixXf& grad_output, bool need_input_grad = true);

  // Inference on any batch (a single column for act()): uses its own scratch buffers, so it
  // neither disturbs the training cache nor allocates after the first call of a given batch size.
  // The returned reference stays valid until the next infer().
  const Eigen::MatrixXf& infer(const Eigen::MatrixXf& x);

  // Allocating, const inference (for code that holds a const network).
  Eigen::MatrixXf evaluate(const Eigen::MatrixXf& x) const;

  void zero_grad();
  // Weight then bias of each layer, input layer first, named "layer<i>.weight"/"layer<i>.bias".
  ParamList params();

  const MlpShape& shape() const { return shape_; }
  int input_size() const { return shape_.input_size; }
  int output_size() const { return shape_.output_size; }
  const std::vector<Dense>& layers() const { return layers_; }
  std::vector<Dense>& layers() { return layers_; }

  // Copies the parameter values (not gradients or caches) of a network of the same shape,
  // e.g. a DQN target network. Throws rdsim::Error when shapes differ.
  void copy_values_from(const Mlp& other);
  // value = tau * other + (1 - tau) * value (Polyak averaging).
  void blend_values_from(const Mlp& other, float tau);

private:
  void run(const Eigen::MatrixXf& x, std::vector<Eigen::MatrixXf>& acts) const;

  MlpShape shape_;
  std::vector<Dense> layers_;
  std::vector<Eigen::MatrixXf> train_acts_;  // [0] = input, [i+1] = output of layer i
  std::vector<Eigen::MatrixXf> infer_acts_;
};

}  // namespace rdsim::nn
