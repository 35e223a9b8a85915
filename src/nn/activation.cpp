#include "rdsim/nn/activation.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim::nn {

Activation activation_from_string(const std::string& name, const std::string& where) {
  if (name == "tanh") return Activation::Tanh;
  if (name == "relu") return Activation::ReLU;
  if (name == "identity") return Activation::Identity;
  throw Error(where + ": expected one of \"tanh\", \"relu\", \"identity\", got \"" + name + "\"");
}

const char* to_string(Activation activation) {
  switch (activation) {
    case Activation::Tanh: return "tanh";
    case Activation::ReLU: return "relu";
    case Activation::Identity: return "identity";
  }
  return "?";
}

void activate(Eigen::MatrixXf& z, Activation activation) {
  switch (activation) {
    case Activation::Tanh: z = z.array().tanh(); break;
    case Activation::ReLU: z = z.cwiseMax(0.0f); break;
    case Activation::Identity: break;
  }
}

void bias_activate(Eigen::MatrixXf& z, const Eigen::Ref<const Eigen::VectorXf>& bias, Activation activation) {
  // Column by column while the column is in cache; the same operations, in the same order per
  // element, as adding the bias to the whole matrix and then activating it.
  for (Eigen::Index j = 0; j < z.cols(); ++j) {
    auto col = z.col(j);
    switch (activation) {
      case Activation::Tanh: col = (col + bias).array().tanh().matrix(); break;
      case Activation::ReLU: col = (col + bias).cwiseMax(0.0f); break;
      case Activation::Identity: col += bias; break;
    }
  }
}

void activation_backward(Eigen::MatrixXf& grad, const Eigen::MatrixXf& y, Activation activation) {
  switch (activation) {
    case Activation::Tanh: grad.array() *= 1.0f - y.array().square(); break;
    case Activation::ReLU: grad = (y.array() > 0.0f).select(grad, 0.0f); break;
    case Activation::Identity: break;
  }
}

}  // namespace rdsim::nn
