#include "rdsim/nn/conv.hpp"

#include <algorithm>
#include <exception>
#include <vector>
#include <type_traits>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/init.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

// Convolution as a matrix product: every output pixel's receptive field is copied into one
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

// How many parts the batch splits into (nn::batch_parts), with a patch buffer for each.
int prepare_parts(const Conv2d& conv, ConvWorkspace& ws, Eigen::Index batch) {
  const double macs = static_cast<double>(conv.spec.out_channels) * conv.patch_size() * conv.output.height *
                      conv.output.width * static_cast<double>(batch);
  const int parts = static_cast<int>(std::min<Eigen::Index>(batch_parts(macs), batch));
  if (static_cast<int>(ws.patches.size()) < parts) ws.patches.resize(static_cast<std::size_t>(parts));
  return parts;
}

// Runs fn(part, first, end) on the samples [first, end) of each of `parts` contiguous parts of
// the batch, each part on a thread of OpenMP's (the threads oneDNN's products use, so no other
// thread spins beside them) with one-threaded products. The first error (lowest part) is rethrown
// once every part has ended. Without OpenMP (a build without oneDNN) parts is always 1.
template <class Fn>
void run_parts(Eigen::Index batch, int parts, Fn fn) {
  if (parts <= 1) {
    fn(0, Eigen::Index{0}, batch);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(parts));
  auto part = [&](int p) {
    try {
      OneThreadedGemm one_thread;
      fn(p, p * batch / parts, (p + 1) * batch / parts);
    } catch (...) {
      errors[static_cast<std::size_t>(p)] = std::current_exception();
    }
  };
#ifdef _OPENMP
  // A team smaller than asked for (the runtime's limits) takes the parts in turn.
#pragma omp parallel num_threads(parts)
  for (int p = omp_get_thread_num(); p < parts; p += omp_get_num_threads()) part(p);
#else
  for (int p = 0; p < parts; ++p) part(p);
#endif
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace

void Conv2d::forward(const Eigen::MatrixXf& x, Eigen::MatrixXf& y, ConvWorkspace& ws) const {
  check_rows("input", x.rows(), in_size());
  const Eigen::Index batch = x.cols();
  y.resize(out_size(), batch);
  if (batch == 0) return;
  const int pixels = output.height * output.width;
  run_parts(batch, prepare_parts(*this, ws, batch), [&](int part, Eigen::Index first, Eigen::Index end) {
    const int chunk = chunk_samples(*this, ws, end - first);
    float* buffer = patch_buffer(*this, ws.patches[static_cast<std::size_t>(part)], static_cast<Eigen::Index>(chunk) * pixels);
    for (Eigen::Index s0 = first; s0 < end; s0 += chunk) {
      const int count = static_cast<int>(std::min<Eigen::Index>(chunk, end - s0));
      transfer_patches<Direction::Gather>(*this, x.col(s0).data(), count, buffer);
      const Eigen::Map<const Eigen::MatrixXf> patches(buffer, patch_size(), static_cast<Eigen::Index>(count) * pixels);
      Eigen::Map<Eigen::MatrixXf> out(y.col(s0).data(), spec.out_channels, static_cast<Eigen::Index>(count) * pixels);
      matmul(weight.value, Op::None, patches, Op::None, out);
      out.colwise() += bias.value.col(0);
    }
  });
}

void Conv2d::backward(const Eigen::MatrixXf& x, const Eigen::MatrixXf& grad_y, Eigen::MatrixXf* grad_x,
                      ConvWorkspace& ws) {
  check_rows("input", x.rows(), in_size());
  check_rows("output gradient", grad_y.rows(), out_size());
  if (grad_y.cols() != x.cols()) throw Error("nn::Conv2d: output gradient and input batch sizes differ");
  const Eigen::Index batch = x.cols();
  if (grad_x) grad_x->setZero(in_size(), batch);
  if (batch == 0) return;
  const int pixels = output.height * output.width;
  const int parts = prepare_parts(*this, ws, batch);
  // Part 0 adds into the layer's gradients as one part always did; the others into their own.
  if (static_cast<int>(ws.weight_grads.size()) < parts - 1) {
    ws.weight_grads.resize(static_cast<std::size_t>(parts - 1));
    ws.bias_grads.resize(static_cast<std::size_t>(parts - 1));
  }
  run_parts(batch, parts, [&](int part, Eigen::Index first, Eigen::Index end) {
    Eigen::MatrixXf* weight_grad = &weight.grad;
    Eigen::MatrixXf* bias_grad = &bias.grad;
    if (part > 0) {
      weight_grad = &ws.weight_grads[static_cast<std::size_t>(part - 1)];
      bias_grad = &ws.bias_grads[static_cast<std::size_t>(part - 1)];
      weight_grad->setZero(weight.grad.rows(), weight.grad.cols());
      bias_grad->setZero(bias.grad.rows(), bias.grad.cols());
    }
    const int chunk = chunk_samples(*this, ws, end - first);
    float* buffer = patch_buffer(*this, ws.patches[static_cast<std::size_t>(part)], static_cast<Eigen::Index>(chunk) * pixels);
    for (Eigen::Index s0 = first; s0 < end; s0 += chunk) {
      const int count = static_cast<int>(std::min<Eigen::Index>(chunk, end - s0));
      const Eigen::Index columns = static_cast<Eigen::Index>(count) * pixels;
      transfer_patches<Direction::Gather>(*this, x.col(s0).data(), count, buffer);
      Eigen::Map<Eigen::MatrixXf> patches(buffer, patch_size(), columns);
      const Eigen::Map<const Eigen::MatrixXf> g(grad_y.col(s0).data(), spec.out_channels, columns);
      matmul(g, Op::None, patches, Op::Transpose, *weight_grad, true);
      bias_grad->col(0) += g.rowwise().sum();
      if (grad_x) {
        matmul(weight.value, Op::Transpose, g, Op::None, patches);
        transfer_patches<Direction::Scatter>(*this, grad_x->col(s0).data(), count, buffer);
      }
    }
  });
  for (int p = 1; p < parts; ++p) {
    weight.grad += ws.weight_grads[static_cast<std::size_t>(p - 1)];
    bias.grad += ws.bias_grads[static_cast<std::size_t>(p - 1)];
  }
}

}  // namespace rdsim::nn
