#include "rdsim/nn/param.hpp"

#include <cmath>

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
