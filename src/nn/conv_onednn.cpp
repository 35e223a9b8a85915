#include "conv_onednn.hpp"

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/error.hpp"

#include "batch_parts.hpp"

#ifdef RDSIM_HAVE_ONEDNN
#include <oneapi/dnnl/dnnl.hpp>
#endif

// Convolution on oneDNN's direct kernels (JIT code for the CPU at hand), which read and write
// rdsim's NHWC batches in place: no patch matrix. Measured on a 2-core AMD EPYC (AVX-512), the
// small CNN's two layers, forward + backward, batch 256 of 84x84x3, one thread: 24.6 ms with
// NHWC data and weights in the layout oneDNN picks, 95.7 ms when the weights too are fixed
// (oneDNN then falls back to its own im2col + GEMM). So the weights are reordered to and from
// the kernels' layout on every call (16 x 192 floats in the first layer: microseconds).
//
// Threads without changing the arithmetic (src/nn/batch_parts.hpp): a large batch is cut into
// parts by its work, every part runs one-threaded kernels, and the parts' weight gradients are
// added in part order, so a layer gives the same bits on one thread or on several.
namespace rdsim::nn {

#ifdef RDSIM_HAVE_ONEDNN
namespace {

using dnnl::memory;
using Tag = memory::format_tag;
constexpr auto kF32 = memory::data_type::f32;

dnnl::engine& cpu_engine() {
  static dnnl::engine engine(dnnl::engine::kind::cpu, 0);
  return engine;
}

memory::dims dims(Eigen::Index samples, const ImageShape& image) {
  return {samples, image.channels, image.height, image.width};
}

// The layer's kernels for parts of `samples` samples.
struct PartKernels {
  ImageShape input;
  ConvSpec spec;
  Eigen::Index samples = 0;
  dnnl::convolution_forward::primitive_desc forward_pd;
  dnnl::convolution_backward_data::primitive_desc data_pd;
  dnnl::convolution_backward_weights::primitive_desc weights_pd;
  dnnl::convolution_forward forward;
  dnnl::convolution_backward_data data;
  dnnl::convolution_backward_weights weights;
  // The layer's weights in the forward and backward-data kernels' layouts, refreshed every call.
  memory forward_weights, data_weights;
};

// Per part: its stream, its share of the weight and bias gradients in the kernel's layout, and
// the kernels' scratch memory (oneDNN's own is one per kernel, not safe to share between parts).
struct PartScratch {
  dnnl::stream stream;
  memory weight_grad, bias_grad;
  std::vector<unsigned char> scratchpad;

  // The scratch memory `pd` asks for, grown as needed.
  template <class PrimitiveDesc>
  memory scratch(const PrimitiveDesc& pd) {
    const memory::desc desc = pd.scratchpad_desc();
    if (scratchpad.size() < desc.get_size()) scratchpad.resize(desc.get_size());
    return memory(desc, stream.get_engine(), scratchpad.data());
  }
};

}  // namespace

struct ConvKernels::Cache {
  std::vector<std::unique_ptr<PartKernels>> kernels;  // owned one by one: callers hold pointers
  std::vector<PartScratch> parts;
  Eigen::MatrixXf weight_grad;  // one part's weight gradient in rdsim's layout
};

namespace {

memory::desc weights_desc(const Conv2d& conv) {
  // rdsim's weight (out x (ky, kx, c), column-major) is oneDNN's "hwio": o innermost.
  return memory::desc({conv.spec.out_channels, conv.input.channels, conv.spec.kernel, conv.spec.kernel}, kF32, Tag::hwio);
}

PartKernels make_kernels(const Conv2d& conv, Eigen::Index samples) {
  const memory::desc src(dims(samples, conv.input), kF32, Tag::nhwc);
  const memory::desc dst(dims(samples, conv.output), kF32, Tag::nhwc);
  const memory::desc weights({conv.spec.out_channels, conv.input.channels, conv.spec.kernel, conv.spec.kernel}, kF32,
                             Tag::any);
  const memory::desc bias({conv.spec.out_channels}, kF32, Tag::x);
  const memory::dims strides{conv.spec.stride, conv.spec.stride}, pad{conv.spec.padding, conv.spec.padding};
  const auto direct = dnnl::algorithm::convolution_direct;
  dnnl::primitive_attr attr;
  attr.set_scratchpad_mode(dnnl::scratchpad_mode::user);
  PartKernels k;
  k.input = conv.input;
  k.spec = conv.spec;
  k.samples = samples;
  k.forward_pd = {{dnnl::prop_kind::forward_training, direct, src, weights, bias, dst, strides, pad, pad}, attr, cpu_engine()};
  k.data_pd = {{direct, src, weights, dst, strides, pad, pad}, attr, cpu_engine(), k.forward_pd};
  k.weights_pd = {{direct, src, weights, bias, dst, strides, pad, pad}, attr, cpu_engine(), k.forward_pd};
  k.forward = dnnl::convolution_forward(k.forward_pd);
  k.data = dnnl::convolution_backward_data(k.data_pd);
  k.weights = dnnl::convolution_backward_weights(k.weights_pd);
  k.forward_weights = memory(k.forward_pd.weights_desc(), cpu_engine());
  k.data_weights = memory(k.data_pd.weights_desc(), cpu_engine());
  return k;
}

// The layer's kernels for parts of `samples` samples, made on first use.
PartKernels& kernels_for(const Conv2d& conv, Eigen::Index samples, ConvKernels::Cache& cache) {
  for (auto& k : cache.kernels)
    if (k->samples == samples && k->input == conv.input && k->spec == conv.spec) return *k;
  cache.kernels.push_back(std::make_unique<PartKernels>(make_kernels(conv, samples)));
  return *cache.kernels.back();
}

// The batch's parts (batch_parts::count of the layer's work).
struct Parts {
  int count = 1;
  Eigen::Index batch = 0;
  Eigen::Index first(int p) const { return batch_parts::first(p, count, batch); }
  Eigen::Index size(int p) const { return first(p + 1) - first(p); }
};

Parts split(const Conv2d& conv, Eigen::Index batch) {
  const double macs = static_cast<double>(conv.spec.out_channels) * conv.patch_size() * conv.output.height *
                      conv.output.width * static_cast<double>(batch);
  return {batch_parts::count(macs, batch), batch};
}

// Every part's kernels (two sizes at most), their weights refreshed from the layer's.
std::vector<PartKernels*> prepare(const Conv2d& conv, const Parts& parts, ConvKernels::Cache& cache, bool data) {
  batch_parts::one_thread();  // kernels made one-threaded: see batch_parts.hpp
  // The cache keeps the most recent kernels: a network sees a handful of batch sizes (rollout,
  // minibatch, evaluation), one layer at a time.
  constexpr std::size_t kKeep = 32;
  while (cache.kernels.size() > kKeep) cache.kernels.erase(cache.kernels.begin());
  std::vector<PartKernels*> kernels;
  for (int p = 0; p < parts.count; ++p) kernels.push_back(&kernels_for(conv, parts.size(p), cache));
  while (static_cast<int>(cache.parts.size()) < parts.count) cache.parts.push_back({dnnl::stream(cpu_engine()), {}, {}, {}});
  memory plain(weights_desc(conv), cpu_engine(), const_cast<float*>(conv.weight.value.data()));
  dnnl::stream& stream = cache.parts.front().stream;
  for (int p = 0; p < parts.count; ++p) {
    if (p > 0 && kernels[static_cast<std::size_t>(p)] == kernels[static_cast<std::size_t>(p - 1)]) continue;
    PartKernels& k = *kernels[static_cast<std::size_t>(p)];
    memory& target = data ? k.data_weights : k.forward_weights;
    dnnl::reorder(plain, target).execute(stream, plain, target);
  }
  stream.wait();
  return kernels;
}

// Runs fn(p) for every part (batch_parts::run), with oneDNN's errors as rdsim's.
void run_parts(int count, const std::function<void(int)>& fn) {
  try {
    batch_parts::run(count, fn);
  } catch (const dnnl::error& error) {
    throw Error(std::string("nn::Conv2d: oneDNN's convolution failed: ") + error.what());
  }
}

memory image_memory(Eigen::Index samples, const ImageShape& image, const float* data) {
  return memory({dims(samples, image), kF32, Tag::nhwc}, cpu_engine(), const_cast<float*>(data));
}

}  // namespace

namespace onednn_conv {

void forward(const Conv2d& conv, const Eigen::MatrixXf& x, Eigen::MatrixXf& y, ConvKernels& kernels) {
  ConvKernels::Cache& cache = kernels.cache();
  const Parts parts = split(conv, x.cols());
  const std::vector<PartKernels*> k = prepare(conv, parts, cache, false);
  const memory bias({{conv.spec.out_channels}, kF32, Tag::x}, cpu_engine(), const_cast<float*>(conv.bias.value.data()));
  run_parts(parts.count, [&](int p) {
    const PartKernels& pk = *k[static_cast<std::size_t>(p)];
    const Eigen::Index first = parts.first(p), n = parts.size(p);
    PartScratch& scratch = cache.parts[static_cast<std::size_t>(p)];
    pk.forward.execute(scratch.stream, {{DNNL_ARG_SRC, image_memory(n, conv.input, x.col(first).data())},
                                        {DNNL_ARG_WEIGHTS, pk.forward_weights},
                                        {DNNL_ARG_BIAS, bias},
                                        {DNNL_ARG_DST, image_memory(n, conv.output, y.col(first).data())},
                                        {DNNL_ARG_SCRATCHPAD, scratch.scratch(pk.forward_pd)}});
    scratch.stream.wait();
  });
}

void backward(Conv2d& conv, const Eigen::MatrixXf& x, const Eigen::MatrixXf& grad_y, Eigen::MatrixXf* grad_x,
              ConvKernels& kernels) {
  ConvKernels::Cache& cache = kernels.cache();
  const Parts parts = split(conv, x.cols());
  const std::vector<PartKernels*> k = prepare(conv, parts, cache, grad_x != nullptr);
  for (int p = 0; p < parts.count; ++p) {
    PartScratch& scratch = cache.parts[static_cast<std::size_t>(p)];
    const PartKernels& pk = *k[static_cast<std::size_t>(p)];
    if (!scratch.weight_grad || scratch.weight_grad.get_desc() != pk.weights_pd.diff_weights_desc())
      scratch.weight_grad = memory(pk.weights_pd.diff_weights_desc(), cpu_engine());
    if (!scratch.bias_grad || scratch.bias_grad.get_desc() != pk.weights_pd.diff_bias_desc())
      scratch.bias_grad = memory(pk.weights_pd.diff_bias_desc(), cpu_engine());
  }
  run_parts(parts.count, [&](int p) {
    const PartKernels& pk = *k[static_cast<std::size_t>(p)];
    PartScratch& scratch = cache.parts[static_cast<std::size_t>(p)];
    const Eigen::Index first = parts.first(p), n = parts.size(p);
    pk.weights.execute(scratch.stream, {{DNNL_ARG_SRC, image_memory(n, conv.input, x.col(first).data())},
                                        {DNNL_ARG_DIFF_DST, image_memory(n, conv.output, grad_y.col(first).data())},
                                        {DNNL_ARG_DIFF_WEIGHTS, scratch.weight_grad},
                                        {DNNL_ARG_DIFF_BIAS, scratch.bias_grad},
                                        {DNNL_ARG_SCRATCHPAD, scratch.scratch(pk.weights_pd)}});
    scratch.stream.wait();
  });
  if (grad_x) {
    run_parts(parts.count, [&](int p) {
      const PartKernels& pk = *k[static_cast<std::size_t>(p)];
      PartScratch& scratch = cache.parts[static_cast<std::size_t>(p)];
      const Eigen::Index first = parts.first(p), n = parts.size(p);
      pk.data.execute(scratch.stream, {{DNNL_ARG_DIFF_DST, image_memory(n, conv.output, grad_y.col(first).data())},
                                       {DNNL_ARG_WEIGHTS, pk.data_weights},
                                       {DNNL_ARG_DIFF_SRC, image_memory(n, conv.input, grad_x->col(first).data())},
                                       {DNNL_ARG_SCRATCHPAD, scratch.scratch(pk.data_pd)}});
      scratch.stream.wait();
    });
  }
  // The parts' gradients, added to the layer's in part order: the same sums on any thread count.
  cache.weight_grad.resize(conv.weight.grad.rows(), conv.weight.grad.cols());
  memory plain(weights_desc(conv), cpu_engine(), cache.weight_grad.data());
  for (int p = 0; p < parts.count; ++p) {
    PartScratch& scratch = cache.parts[static_cast<std::size_t>(p)];
    dnnl::reorder(scratch.weight_grad, plain).execute(scratch.stream, scratch.weight_grad, plain);
    scratch.stream.wait();
    conv.weight.grad += cache.weight_grad;
    conv.bias.grad.col(0) +=
        Eigen::Map<const Eigen::VectorXf>(static_cast<const float*>(scratch.bias_grad.get_data_handle()),
                                          conv.spec.out_channels);
  }
}

}  // namespace onednn_conv

#else  // without oneDNN the backend is always Eigen's and these are never called

struct ConvKernels::Cache {};
namespace onednn_conv {
void forward(const Conv2d&, const Eigen::MatrixXf&, Eigen::MatrixXf&, ConvKernels&) {
  throw Error("nn::Conv2d: this rdsim was built without oneDNN");
}
void backward(Conv2d&, const Eigen::MatrixXf&, const Eigen::MatrixXf&, Eigen::MatrixXf*, ConvKernels&) {
  throw Error("nn::Conv2d: this rdsim was built without oneDNN");
}
}  // namespace onednn_conv

#endif

ConvKernels::ConvKernels() = default;
ConvKernels::~ConvKernels() = default;
ConvKernels::ConvKernels(const ConvKernels&) {}
ConvKernels& ConvKernels::operator=(const ConvKernels&) {
  cache_.reset();
  return *this;
}
ConvKernels::Cache& ConvKernels::cache() {
  if (!cache_) cache_ = std::make_unique<Cache>();
  return *cache_;
}

}  // namespace rdsim::nn
