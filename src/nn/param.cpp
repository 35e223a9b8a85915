#include "rdsim/nn/param.hpp"

#include <cmath>
#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim::nn {

Tensor::Tensor(int rows, int cols)
    : value(Eigen::MatrixXf::Zero(rows, cols)), grad(Eigen::MatrixXf::Zero(rows, cols)) {}

Param param_of(Tensor& tensor, std::string name) {
  return Param{&tensor.value, &tensor.grad, std::move(name)};
}

void append_params(ParamList& list, ParamList part, const std::string& prefix) {
  for (Param& p : part) {
    p.name = prefix + p.name;
    list.push_back(std::move(p));
  }
}

void zero_grad(const ParamList& params) {
  for (const Param& p : params) p.grad->setZero();
}

long long parameter_count(const ParamList& params) {
  long long n = 0;
  for (const Param& p : params) n += p.value->size();
  return n;
}

namespace {

Eigen::VectorXf flatten(const ParamList& params, Eigen::MatrixXf* Param::*member) {
  Eigen::VectorXf flat(parameter_count(params));
  Eigen::Index at = 0;
  for (const Param& p : params) {
    const Eigen::MatrixXf& m = *(p.*member);
    flat.segment(at, m.size()) = Eigen::Map<const Eigen::VectorXf>(m.data(), m.size());
    at += m.size();
  }
  return flat;
}

}  // namespace

Eigen::VectorXf flatten_values(const ParamList& params) { return flatten(params, &Param::value); }
Eigen::VectorXf flatten_grads(const ParamList& params) { return flatten(params, &Param::grad); }

void assign_values(const ParamList& params, const Eigen::Ref<const Eigen::VectorXf>& flat) {
  if (flat.size() != parameter_count(params))
    throw Error("nn::assign_values: got " + std::to_string(flat.size()) + " values for " +
                std::to_string(parameter_count(params)) + " parameters");
  Eigen::Index at = 0;
  for (const Param& p : params) {
    Eigen::Map<Eigen::VectorXf>(p.value->data(), p.value->size()) = flat.segment(at, p.value->size());
    at += p.value->size();
  }
}

float global_grad_norm(const ParamList& params) {
  // Accumulated in double: many small squares in float lose their tail.
  double sum = 0.0;
  for (const Param& p : params) sum += p.grad->cast<double>().squaredNorm();
  return static_cast<float>(std::sqrt(sum));
}

float clip_grad_norm(const ParamList& params, float max_norm) {
  const float norm = global_grad_norm(params);
  if (norm > max_norm) {
    const float scale = max_norm / (norm + 1e-6f);
    for (const Param& p : params) *p.grad *= scale;
  }
  return norm;
}

}  // namespace rdsim::nn
