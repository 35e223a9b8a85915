#include "rdsim/policy/policy_file.hpp"

#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/conv.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim {
namespace {

constexpr char magic[4] = {'R', 'D', 'P', 'P'};
constexpr std::uint32_t version = 1;
// Bounds a damaged file cannot pass: far beyond any network rdsim trains.
constexpr std::uint32_t max_ops = 256;
constexpr std::uint32_t max_values = 1u << 24;  // values per observation at any op
constexpr std::uint32_t max_image_side = 4096;

void write_image(std::ostream& out, const nn::ImageShape& image) {
  write_u32(out, static_cast<std::uint32_t>(image.height));
  write_u32(out, static_cast<std::uint32_t>(image.width));
  write_u32(out, static_cast<std::uint32_t>(image.channels));
}

void write_op(std::ostream& out, const PolicyOp& op) {
  using Kind = PolicyOp::Kind;
  write_u32(out, static_cast<std::uint32_t>(op.kind));
  switch (op.kind) {
    case Kind::Standardize:
      write_f32(out, op.scalar);
      nn::write_matrix(out, op.a);
      nn::write_matrix(out, op.b);
      break;
    case Kind::Scale:
      write_f32(out, op.scalar);
      break;
    case Kind::Dense:
      write_u32(out, static_cast<std::uint32_t>(op.weight.rows()));
      nn::write_matrix(out, op.weight);
      nn::write_matrix(out, op.a);
      break;
    case Kind::Activate:
      write_u32(out, static_cast<std::uint32_t>(op.activation));  // nn::Activation: 0 tanh, 1 relu, 2 identity
      break;
    case Kind::KeepRows:
      write_u32(out, static_cast<std::uint32_t>(op.rows));
      break;
    case Kind::Clip:
    case Kind::Rescale:
      nn::write_matrix(out, op.a);
      nn::write_matrix(out, op.b);
      break;
    case Kind::ArgMax:
      break;
    case Kind::Conv:
      write_image(out, op.conv->input);
      write_u32(out, static_cast<std::uint32_t>(op.conv->spec.out_channels));
      write_u32(out, static_cast<std::uint32_t>(op.conv->spec.kernel));
      write_u32(out, static_cast<std::uint32_t>(op.conv->spec.stride));
      write_u32(out, static_cast<std::uint32_t>(op.conv->spec.padding));
      nn::write_matrix(out, op.conv->weight.value);
      nn::write_matrix(out, op.conv->bias.value);
      break;
  }
}

// Reads the policy op by op, keeping `n`, the values each observation has at the current op.
class Reader {
public:
  Reader(std::string_view bytes, const std::string& source) : in_(std::string(bytes)), source_(source) {}

  PolicyProgram read() {
    char head[4];
    read_bytes(in_, head, 4, source_);
    if (std::memcmp(head, magic, 4) != 0) fail("not a policy (bad magic bytes)");
    const std::uint32_t v = read_u32(in_, source_);
    if (v != version) fail("policy format version " + std::to_string(v) + " is not supported (this rdsim reads 1)");
    PolicyProgram p;
    p.algorithm = read_string(in_, source_);
    if (p.algorithm.empty() || p.algorithm.size() > 64) fail("algorithm name of " + std::to_string(p.algorithm.size()) + " bytes");
    p.input_size = size("input size", max_values);
    p.pixels = flag("pixels");
    if (p.pixels) {
      const nn::ImageShape image = image_shape("image");
      if (image.size() != p.input_size) fail("image " + image.text() + " does not hold the input size " + std::to_string(p.input_size));
      p.image_shape = {image.height, image.width, image.channels};
    }
    p.discrete = flag("discrete");
    p.action_size = size("action size", max_values);
    const std::uint32_t count = read_u32(in_, source_);
    if (count == 0 || count > max_ops) fail(std::to_string(count) + " operations (expected 1 to " + std::to_string(max_ops) + ")");
    n_ = p.input_size;
    for (std::uint32_t i = 0; i < count; ++i) p.ops.push_back(op(i));
    const int outputs = p.discrete ? 1 : p.action_size;
    if (n_ != outputs) fail("its last operation leaves " + std::to_string(n_) + " values per observation, expected " + std::to_string(outputs));
    if (p.discrete != (p.ops.back().kind == PolicyOp::Kind::ArgMax)) fail("a discrete policy ends with argmax, and only it");
    if (bytes_left(in_) != 0) fail("unexpected bytes after its last operation");
    return p;
  }

private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(source_ + ": policy is damaged: " + what); }

  int size(const std::string& what, std::uint32_t max) {
    const std::uint32_t v = read_u32(in_, source_);
    if (v == 0 || v > max) fail(what + " " + std::to_string(v) + " (expected 1 to " + std::to_string(max) + ")");
    return static_cast<int>(v);
  }
  bool flag(const std::string& what) {
    const std::uint32_t v = read_u32(in_, source_);
    if (v > 1) fail(what + " flag " + std::to_string(v) + " (expected 0 or 1)");
    return v == 1;
  }
  nn::ImageShape image_shape(const std::string& what) {
    nn::ImageShape s;
    s.height = size(what + " height", max_image_side);
    s.width = size(what + " width", max_image_side);
    s.channels = size(what + " channels", 64);
    return s;
  }
  Eigen::VectorXf vector(const std::string& what) {
    Eigen::MatrixXf m;
    nn::read_matrix(in_, m, n_, 1, source_, "policy " + what);
    return m.col(0);
  }

  PolicyOp op(std::uint32_t index) {
    using Kind = PolicyOp::Kind;
    const std::string at = "operation " + std::to_string(index + 1);
    PolicyOp op;
    const std::uint32_t kind = read_u32(in_, source_);
    if (kind > static_cast<std::uint32_t>(Kind::Conv)) fail(at + " has unknown kind " + std::to_string(kind));
    op.kind = static_cast<Kind>(kind);
    switch (op.kind) {
      case Kind::Standardize:
        op.scalar = read_f32(in_, source_);
        if (!(op.scalar > 0.0f)) fail(at + ": clip " + std::to_string(op.scalar) + " (expected a positive bound, or infinity)");
        op.a = vector(at + " mean");
        op.b = vector(at + " inverse std");
        break;
      case Kind::Scale:
        op.scalar = read_f32(in_, source_);
        if (!std::isfinite(op.scalar)) fail(at + ": scale is not finite");
        break;
      case Kind::Dense: {
        const int m = size(at + " outputs", max_values);
        if (static_cast<std::uint64_t>(m) * static_cast<std::uint64_t>(n_) > bytes_left(in_) / 4)
          fail(at + ": a " + std::to_string(m) + " x " + std::to_string(n_) + " weight does not fit in the file");
        nn::read_matrix(in_, op.weight, m, n_, source_, "policy " + at + " weight");
        n_ = m;
        op.a = vector(at + " bias");
        break;
      }
      case Kind::Activate: {
        const std::uint32_t a = read_u32(in_, source_);
        if (a > 2) fail(at + ": activation " + std::to_string(a) + " (expected 0 tanh, 1 relu or 2 identity)");
        op.activation = static_cast<nn::Activation>(a);
        break;
      }
      case Kind::KeepRows:
        op.rows = size(at + " rows", static_cast<std::uint32_t>(n_));
        n_ = op.rows;
        break;
      case Kind::Clip:
      case Kind::Rescale:
        op.a = vector(at + " low");
        op.b = vector(at + " high");
        if ((op.a.array() > op.b.array()).any()) fail(at + ": a low bound above its high bound");
        break;
      case Kind::ArgMax:
        n_ = 1;
        break;
      case Kind::Conv:
        op.conv = conv(at);
        n_ = op.conv->out_size();
        break;
    }
    return op;
  }

  std::shared_ptr<const nn::Conv2d> conv(const std::string& at) {
    auto c = std::make_shared<nn::Conv2d>();
    c->input = image_shape(at + " input");
    if (c->input.size() != n_) fail(at + ": input " + c->input.text() + " does not hold the " + std::to_string(n_) + " values it gets");
    c->spec.out_channels = size(at + " out channels", 4096);
    c->spec.kernel = size(at + " kernel", 64);
    c->spec.stride = size(at + " stride", 64);
    c->spec.padding = static_cast<int>(read_u32(in_, source_));
    if (c->spec.padding > 64) fail(at + ": padding " + std::to_string(c->spec.padding) + " (expected 0 to 64)");
    c->output = nn::conv_output_shape(c->input, c->spec, source_ + ": policy " + at);
    const std::uint64_t values = static_cast<std::uint64_t>(c->output.height) * static_cast<std::uint64_t>(c->output.width) *
                                 static_cast<std::uint64_t>(c->output.channels);
    if (values > max_values) fail(at + ": output " + c->output.text() + " is too large");
    nn::read_matrix(in_, c->weight.value, c->spec.out_channels, c->patch_size(), source_, "policy " + at + " weight");
    nn::read_matrix(in_, c->bias.value, c->spec.out_channels, 1, source_, "policy " + at + " bias");
    return c;
  }

  std::istringstream in_;
  const std::string& source_;
  int n_ = 0;
};

}  // namespace

std::string encode_policy_program(const PolicyProgram& p) {
  std::ostringstream out;
  out.write(magic, 4);
  write_u32(out, version);
  write_string(out, p.algorithm);
  write_u32(out, static_cast<std::uint32_t>(p.input_size));
  write_u32(out, p.pixels ? 1 : 0);
  if (p.pixels) {
    for (int d : p.image_shape) write_u32(out, static_cast<std::uint32_t>(d));
  }
  write_u32(out, p.discrete ? 1 : 0);
  write_u32(out, static_cast<std::uint32_t>(p.action_size));
  write_u32(out, static_cast<std::uint32_t>(p.ops.size()));
  for (const PolicyOp& op : p.ops) write_op(out, op);
  return out.str();
}

PolicyProgram decode_policy_program(std::string_view bytes, const std::string& source) {
  return Reader(bytes, source).read();
}

}  // namespace rdsim
