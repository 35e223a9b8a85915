#pragma once
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/nn/param.hpp"

// First-order optimisers over any mix of Params. step() reads the gradients, it does not zero
// them: call zero_grad() before accumulating the next batch.
namespace rdsim::nn {

class Optimizer {
public:
  virtual ~Optimizer() = default;

  // One update from the current gradients.
  virtual void step() = 0;

  void set_learning_rate(float lr) { lr_ = lr; }
  float learning_rate() const { return lr_; }
  const ParamList& params() const { return params_; }

  // Internal state (moments, step count, learning rate) as bytes in the nn stream format.
  virtual void save_state(std::ostream& out) const = 0;
  // Restores what save_state() wrote for the SAME parameter shapes; rdsim::Error naming
  // `source` on a different optimiser type, a shape mismatch or a truncated stream.
  virtual void load_state(std::istream& in, const std::string& source) = 0;

protected:
  Optimizer(ParamList params, float lr) : params_(std::move(params)), lr_(lr) {}
  ParamList params_;
  float lr_;
};

struct AdamConfig {
  float lr = 3e-4f;
  float beta1 = 0.9f;
  float beta2 = 0.999f;
  float eps = 1e-8f;   // added to sqrt(v_hat) (PyTorch/Kingma-Ba placement)
};

// Adam with bias correction: m = b1 m + (1-b1) g; v = b2 v + (1-b2) g^2;
// p -= lr * (m / (1-b1^t)) / (sqrt(v / (1-b2^t)) + eps).
class Adam final : public Optimizer {
public:
  Adam(ParamList params, const AdamConfig& config = {});
  void step() override;
  void save_state(std::ostream& out) const override;
  void load_state(std::istream& in, const std::string& source) override;
  long long steps_taken() const { return t_; }

private:
  AdamConfig config_;
  std::vector<Eigen::MatrixXf> m_, v_;
  long long t_ = 0;
};

struct RmsPropConfig {
  float lr = 7e-4f;
  float alpha = 0.99f;  // decay of the running mean of squared gradients
  float eps = 1e-5f;
  // false (default): PyTorch / Stable-Baselines3 A2C: p -= lr g / (sqrt(s) + eps), s starts at 0.
  // true: TensorFlow / OpenAI-baselines A2C: p -= lr g / sqrt(s + eps), s starts at 1.
  bool tf_style = false;
};

// s = alpha s + (1 - alpha) g^2, then the update chosen by `tf_style` (no momentum, not centred).
class RmsProp final : public Optimizer {
public:
  RmsProp(ParamList params, const RmsPropConfig& config = {});
  void step() override;
  void save_state(std::ostream& out) const override;
  void load_state(std::istream& in, const std::string& source) override;

private:
  RmsPropConfig config_;
  std::vector<Eigen::MatrixXf> square_avg_;
};

}  // namespace rdsim::nn
