#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/rng.hpp"
#include "rdsim/nn/conv.hpp"
#include "rdsim/nn/mlp.hpp"
#include "rdsim/nn/network.hpp"
#include "rdsim/nn/param.hpp"

// Convolutional networks for pixel observations: conv layers (each followed by the activation),
// flatten, then an nn::Mlp head (hidden dense layers + linear output). An nn::Network like
// nn::Mlp, so the RL algorithms hold either without asking which.
//
// Input: (height * width * channels) x batch, ONE COLUMN PER SAMPLE, each column an image in the
// env's layout (HWC, row-major, channels fastest) with the uint8 values already converted to
// float and scaled to [0, 1] by the caller (encode_observation() in observation_batch.hpp does
// exactly that). Two stacked cameras are simply 6 channels.
namespace rdsim::nn {

struct CnnShape {
  ImageShape input;
  std::vector<ConvSpec> convs;
  std::vector<int> hidden_sizes;  // dense layers after the flatten; may be empty
  int output_size = 0;
  Activation activation = Activation::ReLU;  // after every conv and hidden dense layer
};

// Presets (conv stack + dense hidden layers), for any input image and output size:
//  "nature": 32 8x8/4, 64 4x4/2, 64 3x3/1, fc 512 (Mnih et al. 2015; 84x84 -> 7x7x64 = 3136).
//  "small":  16 8x8/4, 32 4x4/2, fc 256 (Mnih et al. 2013). The default for 64x64 images:
//            64x64 -> 15x15x16 -> 6x6x32 = 1152 features, ~4x fewer operations than "nature".
CnnShape nature_cnn(const ImageShape& input, int output_size);
CnnShape small_cnn(const ImageShape& input, int output_size);
// By name ("nature" | "small"); rdsim::Error naming `where` (e.g. "cfg.json: network.cnn") otherwise.
CnnShape cnn_preset(const std::string& name, const ImageShape& input, int output_size,
                    const std::string& where);

class Cnn final : public Network {
public:
  Cnn() = default;
  // Conv and hidden dense layers: orthogonal init with `hidden_gain`; output layer with
  // `output_gain` (baselines: sqrt(2), then 0.01 policy / 1 value or Q head). Zero biases.
  // rdsim::Error on non-positive sizes or a conv stack that does not fit the image.
  // To use the network as a shared feature trunk, give no hidden_sizes and output_size =
  // feature count: the output is then the linear (pre-activation) feature layer.
  Cnn(const CnnShape& shape, float output_gain, Rng& rng, float hidden_gain = 1.41421356f);

  // Memory/speed knob of the conv layers (see ConvWorkspace::max_patch_floats), for training
  // and inference alike. Results do not depend on it beyond float rounding.
  void set_max_patch_floats(long long floats);

  // nn::Network. params(): "conv<i>.weight", "conv<i>.bias" for each conv layer, then the head's
  // parameters prefixed "head." ("head.layer0.weight", ...).
  const Eigen::MatrixXf& forward(const Eigen::MatrixXf& x) override;
  const Eigen::MatrixXf& forward_borrowing(const Eigen::MatrixXf& x) override;
  const Eigen::MatrixXf& infer(const Eigen::MatrixXf& x) override;
  Eigen::MatrixXf evaluate(const Eigen::MatrixXf& x) const override;
  Eigen::MatrixXf backward(const Eigen::MatrixXf& grad_output, bool need_input_grad = true) override;
  ParamList params() override;
  int input_size() const override { return shape_.input.size(); }
  int output_size() const override { return shape_.output_size; }
  std::unique_ptr<Network> clone() const override { return std::make_unique<Cnn>(*this); }

  const CnnShape& shape() const { return shape_; }
  // Number of features entering the dense head (last conv output, flattened HWC).
  int feature_size() const { return head_.input_size(); }
  const std::vector<Conv2d>& convs() const { return convs_; }
  std::vector<Conv2d>& convs() { return convs_; }
  const Mlp& head() const { return head_; }
  Mlp& head() { return head_; }

private:
  // acts[i] = activated output of conv i.
  void run_convs(const Eigen::MatrixXf& x, std::vector<Eigen::MatrixXf>& acts, ConvWorkspace& ws) const;

  CnnShape shape_;
  std::vector<Conv2d> convs_;
  Mlp head_;
  Eigen::MatrixXf train_input_;               // forward()'s copy of its input
  const Eigen::MatrixXf* borrowed_ = nullptr;  // forward_borrowing()'s input, else null
  std::vector<Eigen::MatrixXf> train_acts_, infer_acts_;
  bool has_forward_ = false;
  ConvWorkspace train_ws_, infer_ws_;
  std::vector<Eigen::MatrixXf> conv_grads_;  // backward: dLoss/d(output of conv i)
  Eigen::MatrixXf input_grad_;
};

}  // namespace rdsim::nn
