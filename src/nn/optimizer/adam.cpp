#include <cmath>
#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/optimizer.hpp"
#include "rdsim/nn/serialize.hpp"
#include "../batch_parts.hpp"
#include "../subnormals.hpp"

namespace rdsim::nn {

namespace {
constexpr std::uint32_t kAdamTag = 0x4D414441;  // "ADAM"
}

Adam::Adam(ParamList params, const AdamConfig& config)
    : Optimizer(std::move(params), config.lr), config_(config) {
  for (const Param& p : params_) {
    m_.push_back(Eigen::MatrixXf::Zero(p.value->rows(), p.value->cols()));
    v_.push_back(Eigen::MatrixXf::Zero(p.value->rows(), p.value->cols()));
  }
}

void Adam::step() {
  ++t_;
  const float b1 = config_.beta1, b2 = config_.beta2;
  const double correction1 = 1.0 - std::pow(static_cast<double>(b1), static_cast<double>(t_));
  const double correction2 = 1.0 - std::pow(static_cast<double>(b2), static_cast<double>(t_));
  // Folding the bias corrections into the step size and epsilon keeps one pass per tensor.
  const float step_size = static_cast<float>(lr_ / correction1);
  const float root_c2 = static_cast<float>(std::sqrt(correction2));
  const float eps = config_.eps;
  for (size_t i = 0; i < params_.size(); ++i) {
    // A large tensor in parts side by side, with the same bits as one pass (batch_parts.hpp).
    batch_parts::for_elements(m_[i].size(), [&](Eigen::Index first, Eigen::Index n) {
      // The first moment of a weight whose gradient stays zero (a dead ReLU's) decays by beta1
      // per step into the subnormal floats within a few hundred steps, where every multiply takes
      // the CPU's slow path (measured: Adam took a fifth of SAC + HER's wall-clock on push).
      // Flushed to zero they change no weight in practice (their updates, under 1e-30, are below
      // the last bit of any weight above 1e-23).
      // Set in every part: the flag belongs to the thread that runs it.
      const subnormals::FlushToZero flush;
      const auto g = Eigen::Map<const Eigen::ArrayXf>(params_[i].grad->data() + first, n);
      auto m = Eigen::Map<Eigen::ArrayXf>(m_[i].data() + first, n);
      auto v = Eigen::Map<Eigen::ArrayXf>(v_[i].data() + first, n);
      m = b1 * m + (1.0f - b1) * g;
      v = b2 * v + (1.0f - b2) * g.square();
      Eigen::Map<Eigen::ArrayXf>(params_[i].value->data() + first, n) -= step_size * m / (v.sqrt() / root_c2 + eps);
    });
  }
}

void Adam::save_state(std::ostream& out) const {
  write_u32(out, kAdamTag);
  write_u32(out, static_cast<std::uint32_t>(params_.size()));
  write_u64(out, static_cast<std::uint64_t>(t_));
  write_f32(out, lr_);
  for (size_t i = 0; i < params_.size(); ++i) {
    write_matrix(out, m_[i]);
    write_matrix(out, v_[i]);
  }
}

void Adam::load_state(std::istream& in, const std::string& source) {
  if (read_u32(in, source) != kAdamTag)
    throw Error(source + ": optimiser state is not Adam state (saved with another optimiser?)");
  const std::uint32_t count = read_u32(in, source);
  if (count != params_.size())
    throw Error(source + ": Adam state holds " + std::to_string(count) + " tensors, expected " +
                std::to_string(params_.size()));
  const auto t = static_cast<long long>(read_u64(in, source));
  const float lr = read_f32(in, source);
  if (t < 0 || t > (1LL << 50) || !std::isfinite(lr) || lr < 0.0f)
    throw Error(source + ": Adam state is damaged (step count or learning rate out of range)");
  std::vector<Eigen::MatrixXf> m(params_.size()), v(params_.size());
  for (size_t i = 0; i < params_.size(); ++i) {
    const int rows = static_cast<int>(params_[i].value->rows());
    const int cols = static_cast<int>(params_[i].value->cols());
    read_matrix(in, m[i], rows, cols, source, "Adam first moment of " + params_[i].name);
    read_matrix(in, v[i], rows, cols, source, "Adam second moment of " + params_[i].name);
  }
  t_ = t;
  lr_ = lr;
  m_ = std::move(m);
  v_ = std::move(v);
}

}  // namespace rdsim::nn
