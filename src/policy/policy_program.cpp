#include "rdsim/policy/policy_program.hpp"

#include "rdsim/core/assert.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/nn/conv.hpp"
#include "rdsim/nn/mlp.hpp"

namespace rdsim {

void PolicyProgram::standardize(const Eigen::VectorXf& mean, const Eigen::VectorXf& inverse_std, float clip) {
  PolicyOp op;
  op.kind = PolicyOp::Kind::Standardize;
  op.a = mean;
  op.b = inverse_std;
  op.scalar = clip;
  ops.push_back(std::move(op));
}

void PolicyProgram::scale(float factor) {
  if (factor == 1.0f) return;
  PolicyOp op;
  op.kind = PolicyOp::Kind::Scale;
  op.scalar = factor;
  ops.push_back(std::move(op));
}

void PolicyProgram::mlp(const nn::Mlp& net, bool activate_output) {
  const auto& layers = net.layers();
  for (std::size_t i = 0; i < layers.size(); ++i) {
    PolicyOp op;
    op.kind = PolicyOp::Kind::Dense;
    op.weight = layers[i].weight.value;
    op.a = layers[i].bias.value.col(0);
    ops.push_back(std::move(op));
    if (i + 1 < layers.size() || activate_output) activate(net.shape().activation);
  }
}

void PolicyProgram::cnn(const nn::Cnn& net) {
  for (const nn::Conv2d& conv : net.convs()) {
    PolicyOp op;
    op.kind = PolicyOp::Kind::Conv;
    op.conv = std::make_shared<const nn::Conv2d>(conv);
    ops.push_back(std::move(op));
    activate(net.shape().activation);
  }
  mlp(net.head());
}

void PolicyProgram::activate(nn::Activation activation) {
  if (activation == nn::Activation::Identity) return;
  PolicyOp op;
  op.kind = PolicyOp::Kind::Activate;
  op.activation = activation;
  ops.push_back(std::move(op));
}

void PolicyProgram::keep_rows(int count) {
  PolicyOp op;
  op.kind = PolicyOp::Kind::KeepRows;
  op.rows = count;
  ops.push_back(std::move(op));
}

namespace {

PolicyOp bounds_op(PolicyOp::Kind kind, const Eigen::VectorXf& low, const Eigen::VectorXf& high) {
  PolicyOp op;
  op.kind = kind;
  op.a = low;
  op.b = high;
  return op;
}

}  // namespace

void PolicyProgram::clip(const Eigen::VectorXf& low, const Eigen::VectorXf& high) {
  ops.push_back(bounds_op(PolicyOp::Kind::Clip, low, high));
}

void PolicyProgram::rescale(const Eigen::VectorXf& low, const Eigen::VectorXf& high) {
  ops.push_back(bounds_op(PolicyOp::Kind::Rescale, low, high));
}

void PolicyProgram::argmax() {
  PolicyOp op;
  op.kind = PolicyOp::Kind::ArgMax;
  ops.push_back(std::move(op));
}

Eigen::MatrixXf run_policy_program(const PolicyProgram& program, const Eigen::MatrixXf& x) {
  RDSIM_ASSERT(x.rows() == program.input_size, "observations of the program's input size");
  Eigen::MatrixXf y = x;
  for (const PolicyOp& op : program.ops) {
    switch (op.kind) {
      case PolicyOp::Kind::Standardize:
        y = ((y.colwise() - op.a).array().colwise() * op.b.array()).cwiseMax(-op.scalar).cwiseMin(op.scalar).matrix();
        break;
      case PolicyOp::Kind::Scale:
        y *= op.scalar;
        break;
      case PolicyOp::Kind::Dense: {
        Eigen::MatrixXf z = op.weight * y;
        z.colwise() += op.a;
        y = std::move(z);
        break;
      }
      case PolicyOp::Kind::Activate:
        nn::activate(y, op.activation);
        break;
      case PolicyOp::Kind::KeepRows: {
        Eigen::MatrixXf top = y.topRows(op.rows);
        y = std::move(top);
        break;
      }
      case PolicyOp::Kind::Clip:
        y = y.cwiseMax(op.a.replicate(1, y.cols())).cwiseMin(op.b.replicate(1, y.cols()));
        break;
      case PolicyOp::Kind::Rescale: {
        const Eigen::ArrayXXf unit = y.array().cwiseMax(-1.0f).cwiseMin(1.0f);
        const Eigen::ArrayXf low = op.a.array(), high = op.b.array();
        y = ((0.5f * (unit + 1.0f)).colwise() * (high - low)).colwise() + low;
        y = y.cwiseMin(op.b.replicate(1, y.cols()));
        break;
      }
      case PolicyOp::Kind::Conv: {
        nn::ConvWorkspace workspace;
        Eigen::MatrixXf z;
        op.conv->forward(y, z, workspace);
        y = std::move(z);
        break;
      }
      case PolicyOp::Kind::ArgMax: {
        Eigen::MatrixXf index(1, y.cols());
        for (Eigen::Index c = 0; c < y.cols(); ++c) {
          Eigen::Index best = 0;
          y.col(c).maxCoeff(&best);
          index(0, c) = static_cast<float>(best);
        }
        y = std::move(index);
        break;
      }
    }
  }
  return y;
}

}  // namespace rdsim
