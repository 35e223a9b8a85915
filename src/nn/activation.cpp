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

void activation_backward(Eigen::MatrixXf& grad, const Eigen::MatrixXf& y, Activation activation) {
  switch (activation) {
    case Activation::Tanh: grad.array() *= 1.0f - y.array().square(); break;
    case Activation::ReLU: grad = (y.array() > 0.0f).select(grad, 0.0f); break;
    case Activation::Identity: break;
  }
}

}  // namespace rdsim::nn
