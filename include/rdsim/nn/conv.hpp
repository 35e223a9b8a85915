#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/rng.hpp"
#include "rdsim/nn/param.hpp"

// 2-D convolution on batches of images, one column per sample. A column holds one image
// flattened height x width x channels, row-major ("HWC", the layout pixel observations have),
// so a batch is NHWC in memory. The output uses the same layout, which lets layers chain and a
// dense layer read the last one without any reshuffling.
namespace rdsim::nn {

struct ImageShape {
  int height = 0;
  int width = 0;
  int channels = 0;

  int size() const { return height * width * channels; }
  std::string text() const;  // "84x84x3"
  bool operator==(const ImageShape&) const = default;
};

struct ConvSpec {
  int out_channels = 0;
  int kernel = 0;   // square kernel, kernel x kernel
  int stride = 1;
  int padding = 0;  // zeros added on every side

  std::string text() const;  // "32 8x8/4" (+ " pad 1")
  bool operator==(const ConvSpec&) const = default;
};

// Output image of `spec` applied to `input`: floor((H + 2 pad - kernel) / stride) + 1 per side.
// rdsim::Error naming `where` when a size is not positive or the kernel does not fit.
ImageShape conv_output_shape(const ImageShape& input, const ConvSpec& spec, const std::string& where);

// oneDNN's convolution kernels of the layers a workspace has run, made on first use for each
// layer and part size (src/nn/conv_onednn.cpp). A copy starts empty: kernels hold buffers that
// two networks must not share.
class ConvKernels {
public:
  struct Cache;
  ConvKernels();
  ~ConvKernels();
  ConvKernels(const ConvKernels&);
  ConvKernels& operator=(const ConvKernels&);
  Cache& cache();

private:
  std::unique_ptr<Cache> cache_;
};

// Scratch memory of the convolutions, shared by all layers of a network. It only grows, so
// nothing allocates after the first batch of a given size. Keep one per use (training,
// inference, const evaluation each get their own).
struct ConvWorkspace {
  // Eigen's backend: the im2col patch matrix of one chunk of samples.
  Eigen::VectorXf patches;
  // Samples are processed in chunks whose patch matrix holds at most this many floats
  // (always at least one sample per chunk): bounds memory for big images and keeps the patch
  // matrix in cache. See src/nn/conv.cpp for the measurement behind the default.
  long long max_patch_floats = 1 << 17;
  // oneDNN's backend: its convolution kernels.
  ConvKernels kernels;
};

// y = W * im2col(x) + b. Weight is out_channels x (kernel * kernel * in_channels); its column
// (ky * kernel + kx) * in_channels + c multiplies input channel c at kernel offset (ky, kx).
struct Conv2d {
  ImageShape input;
  ConvSpec spec;
  ImageShape output;
  Tensor weight;
  Tensor bias;  // out_channels x 1

  Conv2d() = default;
  // Orthogonal weights (rows orthonormal when out_channels <= patch size) times `gain`, zero
  // bias (baselines' CNN: gain sqrt(2)). Throws rdsim::Error (naming "nn::Conv2d") on bad sizes.
  Conv2d(const ImageShape& input, const ConvSpec& spec, float gain, Rng& rng);

  int in_size() const { return input.size(); }
  int out_size() const { return output.size(); }
  int patch_size() const { return spec.kernel * spec.kernel * input.channels; }

  // x: in_size x batch -> y: out_size x batch (resized). No activation.
  void forward(const Eigen::MatrixXf& x, Eigen::MatrixXf& y, ConvWorkspace& ws) const;

  // For dLoss/dy of the batch x: ACCUMULATES (+=) into weight.grad and bias.grad and, when
  // grad_x is not null, OVERWRITES *grad_x with dLoss/dx (resized to in_size x batch).
  void backward(const Eigen::MatrixXf& x, const Eigen::MatrixXf& grad_y, Eigen::MatrixXf* grad_x,
                ConvWorkspace& ws);
};

}  // namespace rdsim::nn
