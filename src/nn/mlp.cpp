#include "rdsim/nn/mlp.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/init.hpp"

namespace rdsim::nn {

Dense::Dense(int in, int out, float gain, Rng& rng) : weight(out, in), bias(out, 1) {
  orthogonal_init(weight.value, gain, rng);
}

namespace {

void check_input(const Eigen::MatrixXf& x, int input_size) {
  if (x.rows() != input_size)
    throw Error("nn::Mlp: input has " + std::to_string(x.rows()) + " rows, expected " +
                std::to_string(input_size));
}

}  // namespace

Mlp::Mlp(const MlpShape& shape, float output_gain, Rng& rng, float hidden_gain) : shape_(shape) {
  if (shape.input_size <= 0 || shape.output_size <= 0)
    throw Error("nn::Mlp: input and output sizes must be positive");
  int in = shape.input_size;
  for (int h : shape.hidden_sizes) {
    if (h <= 0) throw Error("nn::Mlp: hidden layer sizes must be positive, got " + std::to_string(h));
    layers_.emplace_back(in, h, hidden_gain, rng);
    in = h;
  }
  layers_.emplace_back(in, shape.output_size, output_gain, rng);
}

void Mlp::run(const Eigen::MatrixXf& x, std::vector<Eigen::MatrixXf>& acts) const {
  check_input(x, shape_.input_size);
  acts.resize(layers_.size() + 1);
  acts[0] = x;
  for (size_t i = 0; i < layers_.size(); ++i) {
    const Dense& layer = layers_[i];
    Eigen::MatrixXf& out = acts[i + 1];
    out.resize(layer.out_size(), x.cols());
    matmul(layer.weight.value, Op::None, acts[i], Op::None, out);
    bias_activate(out, layer.bias.value.col(0), i + 1 < layers_.size() ? shape_.activation : Activation::Identity);
  }
}

const Eigen::MatrixXf& Mlp::forward(const Eigen::MatrixXf& x) {
  run(x, train_acts_);
  return train_acts_.back();
}

const Eigen::MatrixXf& Mlp::infer(const Eigen::MatrixXf& x) {
  run(x, infer_acts_);
  return infer_acts_.back();
}

Eigen::MatrixXf Mlp::evaluate(const Eigen::MatrixXf& x) const {
  std::vector<Eigen::MatrixXf> acts;
  run(x, acts);
  return std::move(acts.back());
}

namespace {

// Multiply-adds from which a layer's two backward products (weight and input gradients, which
// do not depend on each other) run side by side: a hand-over between threads costs microseconds,
// 2^20 multiply-adds some tens of them. A 128 x 128 layer on a batch of 256 is 2^22.
constexpr double kSideBySideMacs = 1 << 20;

}  // namespace

void Mlp::check_backward(const Eigen::MatrixXf& grad_output) const {
  if (train_acts_.empty()) throw Error("nn::Mlp: backward() called before forward()");
  if (grad_output.rows() != shape_.output_size || grad_output.cols() != train_acts_[0].cols())
    throw Error("nn::Mlp: backward() gradient shape does not match the last forward() output");
}

Eigen::MatrixXf Mlp::backward(const Eigen::MatrixXf& grad_output, bool need_input_grad) {
  check_backward(grad_output);
  Eigen::MatrixXf grad = grad_output;
  Eigen::MatrixXf next;
  for (size_t k = layers_.size(); k-- > 0;) {
    Dense& layer = layers_[k];
    if (k + 1 < layers_.size()) activation_backward(grad, train_acts_[k + 1], shape_.activation);
    const bool input = k > 0 || need_input_grad;
    if (input) next.resize(layer.in_size(), grad.cols());
    // Each product writes its own output, so running them side by side gives the same bits.
    auto product = [&](int which) {
      if (which == 0) {
        matmul(grad, Op::None, train_acts_[k], Op::Transpose, layer.weight.grad, true);
        layer.bias.grad += grad.rowwise().sum();
      } else {
        matmul(layer.weight.value, Op::Transpose, grad, Op::None, next);
      }
    };
    const double macs = static_cast<double>(layer.weight.value.size()) * static_cast<double>(grad.cols());
    if (input && macs >= kSideBySideMacs) {
      run_side_by_side(2, product);
    } else {
      product(0);
      if (input) product(1);
    }
    if (!input) return {};
    grad.swap(next);
  }
  return grad;
}

Eigen::MatrixXf Mlp::input_gradient(const Eigen::MatrixXf& grad_output) const {
  check_backward(grad_output);
  Eigen::MatrixXf grad = grad_output;
  Eigen::MatrixXf next;
  for (size_t k = layers_.size(); k-- > 0;) {
    const Dense& layer = layers_[k];
    if (k + 1 < layers_.size()) activation_backward(grad, train_acts_[k + 1], shape_.activation);
    next.resize(layer.in_size(), grad.cols());
    matmul(layer.weight.value, Op::Transpose, grad, Op::None, next);
    grad.swap(next);
  }
  return grad;
}

Eigen::MatrixXf Mlp::jvp(const Eigen::Ref<const Eigen::VectorXf>& direction) const {
  if (train_acts_.empty()) throw Error("nn::Mlp: jvp() called before forward()");
  Eigen::Index count = 0;
  for (const Dense& layer : layers_) count += layer.weight.value.size() + layer.bias.value.size();
  if (direction.size() != count)
    throw Error("nn::Mlp: jvp() direction has " + std::to_string(direction.size()) + " entries, expected " +
                std::to_string(count));
  // z_i = W_i a_i + b_i, so dz_i = dW_i a_i + W_i da_i + db_i, and da_{i+1} = act'(z_i) dz_i.
  Eigen::MatrixXf da, dz;
  Eigen::Index at = 0;
  for (size_t i = 0; i < layers_.size(); ++i) {
    const Dense& layer = layers_[i];
    const Eigen::Index rows = layer.out_size(), cols = layer.in_size();
    const Eigen::Map<const Eigen::MatrixXf> dw(direction.data() + at, rows, cols);
    at += rows * cols;
    const Eigen::Map<const Eigen::VectorXf> db(direction.data() + at, rows);
    at += rows;
    dz.noalias() = dw * train_acts_[i];
    if (i > 0) dz.noalias() += layer.weight.value * da;
    dz.colwise() += db;
    if (i + 1 < layers_.size()) activation_backward(dz, train_acts_[i + 1], shape_.activation);
    da.swap(dz);
  }
  return da;
}

ParamList Mlp::params() {
  ParamList list;
  append_layer_params(list, layers_, "layer");
  return list;
}

}  // namespace rdsim::nn
