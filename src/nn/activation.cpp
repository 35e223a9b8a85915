#include "rdsim/nn/activation.hpp"

#include <algorithm>

#include "batch_parts.hpp"
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

// Elementwise passes over large batches run in parts side by side (batch_parts::for_elements),
// with the same bits as one pass.
void activate(Eigen::MatrixXf& z, Activation activation) {
  if (activation == Activation::Identity) return;
  batch_parts::for_elements(z.size(), [&](Eigen::Index first, Eigen::Index n) {
    auto part = Eigen::Map<Eigen::ArrayXf>(z.data() + first, n);
    if (activation == Activation::Tanh) part = part.tanh();
    else part = part.max(0.0f);
  });
}

void bias_activate(Eigen::MatrixXf& z, const Eigen::Ref<const Eigen::VectorXf>& bias, Activation activation) {
  // Column by column while the column is in cache; the same operations, in the same order per
  // element, as adding the bias to the whole matrix and then activating it. Large batches in
  // parts of whole columns, side by side (each column takes the same path either way).
  batch_parts::for_columns(z.rows(), z.cols(), [&](Eigen::Index first, Eigen::Index count) {
    for (Eigen::Index j = first; j < first + count; ++j) {
      auto col = z.col(j);
      switch (activation) {
        case Activation::Tanh: col = (col + bias).array().tanh().matrix(); break;
        case Activation::ReLU: col = (col + bias).cwiseMax(0.0f); break;
        case Activation::Identity: col += bias; break;
      }
    }
  });
}

void activation_backward(Eigen::MatrixXf& grad, const Eigen::MatrixXf& y, Activation activation) {
  if (activation == Activation::Identity) return;
  if (grad.size() != y.size()) throw Error("nn::activation_backward: gradient and activation sizes differ");
  batch_parts::for_elements(grad.size(), [&](Eigen::Index first, Eigen::Index n) {
    auto g = Eigen::Map<Eigen::ArrayXf>(grad.data() + first, n);
    const auto a = Eigen::Map<const Eigen::ArrayXf>(y.data() + first, n);
    if (activation == Activation::Tanh) g *= 1.0f - a.square();
    else g = (a > 0.0f).select(g, 0.0f);
  });
}

}  // namespace rdsim::nn
