#include "rdsim/nn/cnn.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim::nn {

CnnShape nature_cnn(const ImageShape& input, int output_size) {
  return {input, {{32, 8, 4, 0}, {64, 4, 2, 0}, {64, 3, 1, 0}}, {512}, output_size, Activation::ReLU};
}

CnnShape small_cnn(const ImageShape& input, int output_size) {
  return {input, {{16, 8, 4, 0}, {32, 4, 2, 0}}, {256}, output_size, Activation::ReLU};
}

CnnShape cnn_preset(const std::string& name, const ImageShape& input, int output_size, const std::string& where) {
  if (name == "nature") return nature_cnn(input, output_size);
  if (name == "small") return small_cnn(input, output_size);
  throw Error(where + ": expected one of \"nature\", \"small\", got \"" + name + "\"");
}

Cnn::Cnn(const CnnShape& shape, float output_gain, Rng& rng, float hidden_gain) : shape_(shape) {
  if (shape.output_size <= 0) throw Error("nn::Cnn: the output size must be positive");
  if (shape.input.height <= 0 || shape.input.width <= 0 || shape.input.channels <= 0)
    throw Error("nn::Cnn: input image " + shape.input.text() + " must have positive sizes");
  ImageShape image = shape.input;
  for (size_t i = 0; i < shape.convs.size(); ++i) {
    // Checked here first so the message names the layer.
    conv_output_shape(image, shape.convs[i], "nn::Cnn: conv" + std::to_string(i));
    convs_.emplace_back(image, shape.convs[i], hidden_gain, rng);
    image = convs_.back().output;
  }
  head_ = Mlp({image.size(), shape.hidden_sizes, shape.output_size, shape.activation}, output_gain, rng, hidden_gain);
}

void Cnn::run_convs(const Eigen::MatrixXf& x, std::vector<Eigen::MatrixXf>& acts, ConvWorkspace& ws) const {
  if (x.rows() != input_size())
    throw Error("nn::Cnn: input has " + std::to_string(x.rows()) + " rows, expected " +
                std::to_string(input_size()) + " (" + shape_.input.text() + " image)");
  acts.resize(convs_.size());
  const Eigen::MatrixXf* in = &x;
  for (size_t i = 0; i < convs_.size(); ++i) {
    convs_[i].forward(*in, acts[i], ws);
    activate(acts[i], shape_.activation);
    in = &acts[i];
  }
}

const Eigen::MatrixXf& Cnn::forward(const Eigen::MatrixXf& x) {
  run_convs(x, train_acts_, train_ws_);
  train_input_ = x;
  borrowed_ = nullptr;
  has_forward_ = true;
  return head_.forward(convs_.empty() ? x : train_acts_.back());
}

const Eigen::MatrixXf& Cnn::forward_borrowing(const Eigen::MatrixXf& x) {
  run_convs(x, train_acts_, train_ws_);
  borrowed_ = &x;
  has_forward_ = true;
  return head_.forward(convs_.empty() ? x : train_acts_.back());
}

const Eigen::MatrixXf& Cnn::infer(const Eigen::MatrixXf& x) {
  run_convs(x, infer_acts_, infer_ws_);
  return head_.infer(convs_.empty() ? x : infer_acts_.back());
}

Eigen::MatrixXf Cnn::evaluate(const Eigen::MatrixXf& x) const {
  std::vector<Eigen::MatrixXf> acts;
  ConvWorkspace ws;
  run_convs(x, acts, ws);
  return head_.evaluate(convs_.empty() ? x : acts.back());
}

Eigen::MatrixXf Cnn::backward(const Eigen::MatrixXf& grad_output, bool need_input_grad) {
  if (!has_forward_) throw Error("nn::Cnn: backward() called before forward()");
  // The head checks grad_output against its last forward() batch.
  Eigen::MatrixXf head_grad = head_.backward(grad_output, need_input_grad || !convs_.empty());
  if (convs_.empty()) return head_grad;
  // One gradient buffer per conv output, kept between calls: batches of images are megabytes, and
  // a buffer that changes size on every call costs page faults on every call.
  conv_grads_.resize(convs_.size());
  conv_grads_.back().swap(head_grad);
  for (size_t k = convs_.size(); k-- > 0;) {
    activation_backward(conv_grads_[k], train_acts_[k], shape_.activation);
    const Eigen::MatrixXf& in = k > 0 ? train_acts_[k - 1] : borrowed_ ? *borrowed_ : train_input_;
    Eigen::MatrixXf* grad_in = k > 0 ? &conv_grads_[k - 1] : need_input_grad ? &input_grad_ : nullptr;
    convs_[k].backward(in, conv_grads_[k], grad_in, train_ws_);
  }
  if (!need_input_grad) return {};
  return input_grad_;
}

void Cnn::set_max_patch_floats(long long floats) {
  train_ws_.max_patch_floats = floats;
  infer_ws_.max_patch_floats = floats;
}

ParamList Cnn::params() {
  ParamList list;
  append_layer_params(list, convs_, "conv");
  append_params(list, head_.params(), "head.");
  return list;
}

}  // namespace rdsim::nn
