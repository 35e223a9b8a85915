#include "rdsim/nn/conv.hpp"

#include <algorithm>
#include <type_traits>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/init.hpp"
#include "conv_onednn.hpp"

// Eigen's backend computes a convolution as a matrix product (oneDNN's backend runs oneDNN's own
// convolution kernels instead: src/nn/conv_onednn.cpp): every output pixel's receptive field is copied into one
// column of a patch matrix ("im2col"), then one GEMM per chunk of samples computes all output
// channels of all those pixels. With HWC images a patch row (one kernel row, all channels) is
// a contiguous run of the input, so im2col is a handful of memcpy's per output pixel, and the
// GEMM result (out_channels x pixels, column-major) already is the HWC output image.
//
// Chunking (ConvWorkspace::max_patch_floats), measured on the 2-core dev box (Release, SSE2,
// one thread), "small" CNN at 64x64x3, batch 256, forward+backward per sample:
//   one sample per chunk 274 us, 2^17 floats 229 us, 2^19 floats 227 us, 2^21 floats 232 us,
//   whole batch in one GEMM (44 MB patch matrix) 254 us.
// The patch matrix is rebuilt in backward() rather than cached: im2col costs a few percent of
// the GEMMs, and caching would need the whole batch's patches (hundreds of MB at 224x224).
namespace rdsim::nn {

std::string ImageShape::text() const {
  return std::to_string(height) + "x" + std::to_string(width) + "x" + std::to_string(channels);
}

std::string ConvSpec::text() const {
  std::string s = std::to_string(out_channels) + " " + std::to_string(kernel) + "x" +
                  std::to_string(kernel) + "/" + std::to_string(stride);
  if (padding != 0) s += " pad " + std::to_string(padding);
  return s;
}

ImageShape conv_output_shape(const ImageShape& input, const ConvSpec& spec, const std::string& where) {
  if (input.height <= 0 || input.width <= 0 || input.channels <= 0)
    throw Error(where + ": input image " + input.text() + " must have positive sizes");
  if (spec.out_channels <= 0 || spec.kernel <= 0 || spec.stride <= 0 || spec.padding < 0)
    throw Error(where + ": conv \"" + spec.text() +
                "\" needs positive channels, kernel and stride and a non-negative padding");
  const int h = input.height + 2 * spec.padding - spec.kernel;
  const int w = input.width + 2 * spec.padding - spec.kernel;
  if (h < 0 || w < 0)
    throw Error(where + ": conv \"" + spec.text() + "\" does not fit its " + input.text() +
                " input (kernel larger than the padded image)");
  return {h / spec.stride + 1, w / spec.stride + 1, spec.out_channels};
}

Conv2d::Conv2d(const ImageShape& in, const ConvSpec& s, float gain, Rng& rng)
    : input(in),
      spec(s),
      output(conv_output_shape(in, s, "nn::Conv2d")),
      weight(s.out_channels, s.kernel * s.kernel * in.channels),
      bias(s.out_channels, 1) {
  orthogonal_init(weight.value, gain, rng);
}

namespace {

enum class Direction { Gather, Scatter };

// Gather: copies the patches of `count` consecutive HWC images starting at `images` into the
// columns of `patches` (patch_size x count*pixels), zeros where the kernel hangs over the
// padding. Scatter: the adjoint, adds every patch entry back onto the image pixel it came from.
template <Direction dir>
using ImagePtr = std::conditional_t<dir == Direction::Gather, const float*, float*>;
template <Direction dir>
using PatchPtr = std::conditional_t<dir == Direction::Gather, float*, const float*>;

// Gather without padding: every patch row lies inside the image, so a patch is K contiguous
// runs of K x C floats, copied with a vector loop of the row's length fixed per layer.
void gather_unpadded(const Conv2d& conv, const float* images, int count, float* patches) {
  const int W = conv.input.width, C = conv.input.channels, K = conv.spec.kernel, S = conv.spec.stride;
  const Eigen::Index row_len = K * C;
  const std::ptrdiff_t image_size = conv.input.size();
  float* column = patches;
  for (int n = 0; n < count; ++n) {
    const float* image = images + n * image_size;
    for (int oy = 0; oy < conv.output.height; ++oy) {
      for (int ox = 0; ox < conv.output.width; ++ox) {
        const float* from = image + (static_cast<std::ptrdiff_t>(oy) * S * W + ox * S) * C;
        for (int ky = 0; ky < K; ++ky, column += row_len, from += W * C)
          Eigen::Map<Eigen::ArrayXf>(column, row_len) = Eigen::Map<const Eigen::ArrayXf>(from, row_len);
      }
    }
  }
}

template <Direction dir>
void transfer_patches(const Conv2d& conv, ImagePtr<dir> images, int count, PatchPtr<dir> patches) {
  const int H = conv.input.height, W = conv.input.width, C = conv.input.channels;
  const int K = conv.spec.kernel, S = conv.spec.stride, P = conv.spec.padding;
  const int row_len = K * C;
  if constexpr (dir == Direction::Gather) {
    if (P == 0) return gather_unpadded(conv, images, count, patches);
  }
  PatchPtr<dir> column = patches;
  for (int n = 0; n < count; ++n) {
    ImagePtr<dir> image = images + static_cast<std::ptrdiff_t>(n) * H * W * C;
    for (int oy = 0; oy < conv.output.height; ++oy) {
      for (int ox = 0; ox < conv.output.width; ++ox, column += K * row_len) {
        const int y0 = oy * S - P, x0 = ox * S - P;
        const int kx_begin = std::max(0, -x0), kx_end = std::min(K, W - x0);
        for (int ky = 0; ky < K; ++ky) {
          PatchPtr<dir> patch_row = column + ky * row_len;
          const int iy = y0 + ky;
          const bool row_inside = iy >= 0 && iy < H && kx_begin < kx_end;
          if constexpr (dir == Direction::Gather) {
            if (!row_inside) {
              std::fill(patch_row, patch_row + row_len, 0.0f);
              continue;
            }
            std::fill(patch_row, patch_row + kx_begin * C, 0.0f);
            // An inlined vector copy: a patch row is short (kernel x channels floats, 24 for the
            // first layer of the CNNs), and a memcpy call per row cost a fifth of an update.
            const Eigen::Index len = (kx_end - kx_begin) * C;
            Eigen::Map<Eigen::ArrayXf>(patch_row + kx_begin * C, len) =
                Eigen::Map<const Eigen::ArrayXf>(image + (iy * W + x0 + kx_begin) * C, len);
            std::fill(patch_row + kx_end * C, patch_row + row_len, 0.0f);
          } else {
            if (!row_inside) continue;
            float* pixels = image + (iy * W + x0 + kx_begin) * C;
            const float* from = patch_row + kx_begin * C;
            const Eigen::Index len = (kx_end - kx_begin) * C;
            Eigen::Map<Eigen::ArrayXf>(pixels, len) += Eigen::Map<const Eigen::ArrayXf>(from, len);
          }
        }
      }
    }
  }
}

// Samples per chunk so that the patch matrix stays within the workspace budget.
int chunk_samples(const Conv2d& conv, const ConvWorkspace& ws, Eigen::Index batch) {
  const long long per_sample = static_cast<long long>(conv.patch_size()) * conv.output.height * conv.output.width;
  const long long fit = std::max(1LL, ws.max_patch_floats / per_sample);
  return static_cast<int>(std::min<long long>(fit, batch));
}

// A patch buffer grown (never shrunk) to hold `columns` patch columns. Growing by size only, not
// shape, matters: layers with different patch sizes share the buffer, and re-allocating a large
// one on every layer costs page faults on every call.
float* patch_buffer(const Conv2d& conv, Eigen::VectorXf& patches, Eigen::Index columns) {
  const Eigen::Index needed = conv.patch_size() * columns;
  if (patches.size() < needed) patches.resize(needed);
  return patches.data();
}

void check_rows(const char* what, Eigen::Index rows, int expected) {
  if (rows != expected)
    throw Error(std::string("nn::Conv2d: ") + what + " has " + std::to_string(rows) + " rows, expected " +
                std::to_string(expected));
}

}  // namespace

void Conv2d::forward(const Eigen::MatrixXf& x, Eigen::MatrixXf& y, ConvWorkspace& ws) const {
  check_rows("input", x.rows(), in_size());
  const Eigen::Index batch = x.cols();
  y.resize(out_size(), batch);
  if (batch == 0) return;
  if (gemm_backend() == GemmBackend::OneDnn) return onednn_conv::forward(*this, x, y, ws.kernels);
  const int pixels = output.height * output.width;
  const int chunk = chunk_samples(*this, ws, batch);
  float* buffer = patch_buffer(*this, ws.patches, static_cast<Eigen::Index>(chunk) * pixels);
  for (Eigen::Index s0 = 0; s0 < batch; s0 += chunk) {
    const int count = static_cast<int>(std::min<Eigen::Index>(chunk, batch - s0));
    transfer_patches<Direction::Gather>(*this, x.col(s0).data(), count, buffer);
    const Eigen::Map<const Eigen::MatrixXf> patches(buffer, patch_size(), static_cast<Eigen::Index>(count) * pixels);
    Eigen::Map<Eigen::MatrixXf> out(y.col(s0).data(), spec.out_channels, static_cast<Eigen::Index>(count) * pixels);
    matmul(weight.value, Op::None, patches, Op::None, out);
    out.colwise() += bias.value.col(0);
  }
}

void Conv2d::backward(const Eigen::MatrixXf& x, const Eigen::MatrixXf& grad_y, Eigen::MatrixXf* grad_x,
                      ConvWorkspace& ws) {
  check_rows("input", x.rows(), in_size());
  check_rows("output gradient", grad_y.rows(), out_size());
  if (grad_y.cols() != x.cols()) throw Error("nn::Conv2d: output gradient and input batch sizes differ");
  const Eigen::Index batch = x.cols();
  if (gemm_backend() == GemmBackend::OneDnn) {
    if (grad_x) grad_x->resize(in_size(), batch);  // oneDNN writes every entry
    if (batch > 0) onednn_conv::backward(*this, x, grad_y, grad_x, ws.kernels);
    return;
  }
  if (grad_x) grad_x->setZero(in_size(), batch);
  if (batch == 0) return;
  const int pixels = output.height * output.width;
  const int chunk = chunk_samples(*this, ws, batch);
  float* buffer = patch_buffer(*this, ws.patches, static_cast<Eigen::Index>(chunk) * pixels);
  for (Eigen::Index s0 = 0; s0 < batch; s0 += chunk) {
    const int count = static_cast<int>(std::min<Eigen::Index>(chunk, batch - s0));
    const Eigen::Index columns = static_cast<Eigen::Index>(count) * pixels;
    transfer_patches<Direction::Gather>(*this, x.col(s0).data(), count, buffer);
    Eigen::Map<Eigen::MatrixXf> patches(buffer, patch_size(), columns);
    const Eigen::Map<const Eigen::MatrixXf> g(grad_y.col(s0).data(), spec.out_channels, columns);
    matmul(g, Op::None, patches, Op::Transpose, weight.grad, true);
    bias.grad.col(0) += g.rowwise().sum();
    if (grad_x) {
      matmul(weight.value, Op::Transpose, g, Op::None, patches);
      transfer_patches<Direction::Scatter>(*this, grad_x->col(s0).data(), count, buffer);
    }
  }
}

}  // namespace rdsim::nn
