#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/rng.hpp"
#include "rdsim/nn/activation.hpp"
#include "rdsim/nn/network.hpp"
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

// Dense layers with the activation after each hidden layer and a linear output.
class Mlp final : public Network {
public:
  Mlp() = default;
  // Hidden layers: orthogonal init with `hidden_gain`; output layer with `output_gain`
  // (baselines: sqrt(2) hidden, 0.01 policy head, 1 value head). Biases start at zero.
  // Throws rdsim::Error on non-positive sizes.
  Mlp(const MlpShape& shape, float output_gain, Rng& rng, float hidden_gain = 1.41421356f);

  // nn::Network; params() are "layer<i>.weight", "layer<i>.bias" of each layer, input layer first.
  const Eigen::MatrixXf& forward(const Eigen::MatrixXf& x) override;
  Eigen::MatrixXf backward(const Eigen::MatrixXf& grad_output, bool need_input_grad = true) override;
  const Eigen::MatrixXf& infer(const Eigen::MatrixXf& x) override;
  Eigen::MatrixXf evaluate(const Eigen::MatrixXf& x) const override;
  ParamList params() override;

  // dLoss/dInput (input_size x batch) of the LAST forward() batch, the parameter gradients left
  // untouched: an actor's loss back through a critic that this loss does not train (SAC's and
  // TD3's actor steps), with half the products of backward().
  Eigen::MatrixXf input_gradient(const Eigen::MatrixXf& grad_output) const;
  int input_size() const override { return shape_.input_size; }
  int output_size() const override { return shape_.output_size; }
  std::unique_ptr<Network> clone() const override { return std::make_unique<Mlp>(*this); }

  // Forward-mode derivative of the LAST forward() output along a direction in parameter space,
  // the input held fixed: sum_k d output / d theta_k * direction_k (output_size x batch), where
  // `direction` is laid out as flatten_values(params()). TRPO's Fisher-vector products use it.
  Eigen::MatrixXf jvp(const Eigen::Ref<const Eigen::VectorXf>& direction) const;

  const MlpShape& shape() const { return shape_; }
  const std::vector<Dense>& layers() const { return layers_; }
  std::vector<Dense>& layers() { return layers_; }

private:
  void run(const Eigen::MatrixXf& x, std::vector<Eigen::MatrixXf>& acts) const;
  void check_backward(const Eigen::MatrixXf& grad_output) const;

  MlpShape shape_;
  std::vector<Dense> layers_;
  std::vector<Eigen::MatrixXf> train_acts_;  // [0] = input, [i+1] = output of layer i
  std::vector<Eigen::MatrixXf> infer_acts_;
};

}  // namespace rdsim::nn
