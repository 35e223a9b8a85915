#include <istream>
#include <ostream>

#include <cmath>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/optimizer.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim::nn {

namespace {
constexpr std::uint32_t kRmsPropTag = 0x504D5352;  // "RSMP"
}

RmsProp::RmsProp(ParamList params, const RmsPropConfig& config)
    : Optimizer(std::move(params), config.lr), config_(config) {
  // TensorFlow starts the running mean at 1, which damps the first updates.
  const float start = config.tf_style ? 1.0f : 0.0f;
  for (const Param& p : params_)
    square_avg_.push_back(Eigen::MatrixXf::Constant(p.value->rows(), p.value->cols(), start));
}

void RmsProp::step() {
  const float alpha = config_.alpha, eps = config_.eps;
  for (size_t i = 0; i < params_.size(); ++i) {
    auto g = params_[i].grad->array();
    auto s = square_avg_[i].array();
    s = alpha * s + (1.0f - alpha) * g.square();
    if (config_.tf_style)
      params_[i].value->array() -= lr_ * g / (s + eps).sqrt();
    else
      params_[i].value->array() -= lr_ * g / (s.sqrt() + eps);
  }
}

void RmsProp::save_state(std::ostream& out) const {
  write_u32(out, kRmsPropTag);
  write_u32(out, static_cast<std::uint32_t>(params_.size()));
  write_f32(out, lr_);
  for (const Eigen::MatrixXf& s : square_avg_) write_matrix(out, s);
}

void RmsProp::load_state(std::istream& in, const std::string& source) {
  if (read_u32(in, source) != kRmsPropTag)
    throw Error(source + ": optimiser state is not RMSprop state (saved with another optimiser?)");
  const std::uint32_t count = read_u32(in, source);
  if (count != params_.size())
    throw Error(source + ": RMSprop state holds " + std::to_string(count) + " tensors, expected " +
                std::to_string(params_.size()));
  const float lr = read_f32(in, source);
  if (!std::isfinite(lr) || lr < 0.0f) throw Error(source + ": RMSprop state is damaged (learning rate out of range)");
  std::vector<Eigen::MatrixXf> square_avg(params_.size());
  for (size_t i = 0; i < params_.size(); ++i)
    read_matrix(in, square_avg[i], static_cast<int>(params_[i].value->rows()),
                static_cast<int>(params_[i].value->cols()), source,
                "RMSprop running mean of " + params_[i].name);
  lr_ = lr;
  square_avg_ = std::move(square_avg);
}

}  // namespace rdsim::nn
