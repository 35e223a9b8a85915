#include "rdsim/export/onnx_export.hpp"

#include <onnx/checker.h>
#include <onnx/onnx_pb.h>

#include <vector>

#include "rdsim/nn/conv.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

constexpr int opset = 13;         // Gemm, Clip with tensor bounds, Slice with tensor starts, ArgMax
constexpr int ir_version = 7;     // the IR of opset 13

// "c12": a generated name (appended, not `"c" + std::to_string(n)`, which GCC 12 warns about wrongly).
std::string numbered(const char* prefix, int n) {
  std::string name = prefix;
  name += std::to_string(n);
  return name;
}

// Builds the graph one node at a time, each taking the previous output.
class GraphBuilder {
public:
  explicit GraphBuilder(onnx::GraphProto& graph) : graph_(graph) {}

  // A float32 constant of the given shape, values in row-major order.
  std::string constant(const std::vector<std::int64_t>& dims, const std::vector<float>& values) {
    onnx::TensorProto* t = graph_.add_initializer();
    t->set_name(numbered("c", counter_++));
    t->set_data_type(onnx::TensorProto::FLOAT);
    for (std::int64_t d : dims) t->add_dims(d);
    for (float v : values) t->add_float_data(v);
    return t->name();
  }
  std::string vector(const Eigen::VectorXf& v) {
    return constant({v.size()}, std::vector<float>(v.data(), v.data() + v.size()));
  }
  std::string scalar(float v) { return constant({}, {v}); }
  std::string int64s(const std::vector<std::int64_t>& values) {
    onnx::TensorProto* t = graph_.add_initializer();
    t->set_name(numbered("c", counter_++));
    t->set_data_type(onnx::TensorProto::INT64);
    t->add_dims(static_cast<std::int64_t>(values.size()));
    for (std::int64_t v : values) t->add_int64_data(v);
    return t->name();
  }

  // One node of `type` on `inputs`; returns its output's name.
  onnx::NodeProto* node(const std::string& type, const std::vector<std::string>& inputs) {
    onnx::NodeProto* n = graph_.add_node();
    n->set_op_type(type);
    n->set_name(numbered((type + "_").c_str(), counter_));
    for (const std::string& i : inputs) n->add_input(i);
    n->add_output(numbered("t", counter_++));
    return n;
  }
  std::string apply(const std::string& type, const std::vector<std::string>& inputs) { return node(type, inputs)->output(0); }

private:
  onnx::GraphProto& graph_;
  int counter_ = 0;
};

void set_int_attribute(onnx::NodeProto* n, const char* name, std::int64_t value) {
  onnx::AttributeProto* a = n->add_attribute();
  a->set_name(name);
  a->set_type(onnx::AttributeProto::INT);
  a->set_i(value);
}

void set_ints_attribute(onnx::NodeProto* n, const char* name, const std::vector<std::int64_t>& values) {
  onnx::AttributeProto* a = n->add_attribute();
  a->set_name(name);
  a->set_type(onnx::AttributeProto::INTS);
  for (std::int64_t v : values) a->add_ints(v);
}

void add_value_info(onnx::ValueInfoProto* info, const std::string& name, int type, const std::vector<std::int64_t>& dims) {
  info->set_name(name);
  onnx::TypeProto_Tensor* tensor = info->mutable_type()->mutable_tensor_type();
  tensor->set_elem_type(type);
  onnx::TensorShapeProto* shape = tensor->mutable_shape();
  shape->add_dim()->set_dim_param("batch");
  for (std::int64_t d : dims) shape->add_dim()->set_dim_value(d);
}

// A convolution on `x` ([batch, height * width * channels], rdsim's layout): to NCHW images, ONNX's
// Conv, and back to rdsim's flattened layout.
std::string add_conv(GraphBuilder& g, const nn::Conv2d& conv, const std::string& x) {
  const nn::ImageShape& in = conv.input;
  const nn::ImageShape& out = conv.output;
  const std::int64_t k = conv.spec.kernel, pad = conv.spec.padding, stride = conv.spec.stride;
  const std::string images = g.apply("Reshape", {x, g.int64s({-1, in.height, in.width, in.channels})});
  onnx::NodeProto* to_nchw = g.node("Transpose", {images});
  set_ints_attribute(to_nchw, "perm", {0, 3, 1, 2});
  // nn::Conv2d's weight column (ky * k + kx) * in_channels + c is ONNX's W[o][c][ky][kx].
  std::vector<float> w;
  w.reserve(static_cast<std::size_t>(conv.weight.value.size()));
  for (int o = 0; o < out.channels; ++o)
    for (int c = 0; c < in.channels; ++c)
      for (std::int64_t ky = 0; ky < k; ++ky)
        for (std::int64_t kx = 0; kx < k; ++kx) w.push_back(conv.weight.value(o, (ky * k + kx) * in.channels + c));
  onnx::NodeProto* node = g.node("Conv", {to_nchw->output(0), g.constant({out.channels, in.channels, k, k}, w),
                                          g.vector(conv.bias.value.col(0))});
  set_ints_attribute(node, "kernel_shape", {k, k});
  set_ints_attribute(node, "strides", {stride, stride});
  set_ints_attribute(node, "pads", {pad, pad, pad, pad});
  onnx::NodeProto* to_nhwc = g.node("Transpose", {node->output(0)});
  set_ints_attribute(to_nhwc, "perm", {0, 2, 3, 1});
  return g.apply("Reshape", {to_nhwc->output(0), g.int64s({-1, static_cast<std::int64_t>(out.size())})});
}

// The nodes of one op on `x` ([batch, features]); returns the result's name.
std::string add_op(GraphBuilder& g, const PolicyOp& op, const std::string& x) {
  using Kind = PolicyOp::Kind;
  switch (op.kind) {
    case Kind::Standardize: {
      const std::string centred = g.apply("Sub", {x, g.vector(op.a)});
      const std::string scaled = g.apply("Mul", {centred, g.vector(op.b)});
      return g.apply("Clip", {scaled, g.scalar(-op.scalar), g.scalar(op.scalar)});
    }
    case Kind::Scale:
      return g.apply("Mul", {x, g.scalar(op.scalar)});
    case Kind::Dense: {
      // Gemm: x [batch, in] times weight^T, weight [out, in] row-major, plus bias [out].
      std::vector<float> w;
      w.reserve(static_cast<std::size_t>(op.weight.size()));
      for (Eigen::Index r = 0; r < op.weight.rows(); ++r)
        for (Eigen::Index c = 0; c < op.weight.cols(); ++c) w.push_back(op.weight(r, c));
      onnx::NodeProto* n = g.node("Gemm", {x, g.constant({op.weight.rows(), op.weight.cols()}, w), g.vector(op.a)});
      set_int_attribute(n, "transB", 1);
      return n->output(0);
    }
    case Kind::Activate:
      switch (op.activation) {
        case nn::Activation::Tanh:
          return g.apply("Tanh", {x});
        case nn::Activation::ReLU:
          return g.apply("Relu", {x});
        case nn::Activation::Identity:
          return x;
      }
      return x;
    case Kind::KeepRows:
      return g.apply("Slice", {x, g.int64s({0}), g.int64s({op.rows}), g.int64s({1})});
    case Kind::Clip:
      return g.apply("Min", {g.apply("Max", {x, g.vector(op.a)}), g.vector(op.b)});
    case Kind::Rescale: {
      const std::string unit = g.apply("Clip", {x, g.scalar(-1.0f), g.scalar(1.0f)});
      const std::string shifted = g.apply("Add", {unit, g.scalar(1.0f)});
      const Eigen::VectorXf half_range = 0.5f * (op.b - op.a);
      const std::string spread = g.apply("Mul", {shifted, g.vector(half_range)});
      return g.apply("Min", {g.apply("Add", {spread, g.vector(op.a)}), g.vector(op.b)});
    }
    case Kind::Conv:
      return add_conv(g, *op.conv, x);
    case Kind::ArgMax: {
      onnx::NodeProto* n = g.node("ArgMax", {x});
      set_int_attribute(n, "axis", 1);
      set_int_attribute(n, "keepdims", 0);
      return n->output(0);
    }
  }
  return x;
}

}  // namespace

std::string onnx_model_bytes(const PolicyProgram& program, const std::map<std::string, std::string>& metadata) {
  onnx::ModelProto model;
  model.set_ir_version(ir_version);
  model.set_producer_name("rdsim");
  model.set_doc_string("rdsim " + program.algorithm + " policy: the deterministic action for a batch of observations");
  onnx::OperatorSetIdProto* set = model.add_opset_import();
  set->set_domain("");
  set->set_version(opset);
  for (const auto& [key, value] : metadata) {
    onnx::StringStringEntryProto* entry = model.add_metadata_props();
    entry->set_key(key);
    entry->set_value(value);
  }
  onnx::GraphProto* graph = model.mutable_graph();
  graph->set_name(program.algorithm + "_policy");
  GraphBuilder g(*graph);
  std::string x = "observation";
  if (program.pixels) {
    // uint8 images [batch, height, width, channels], encoded as rdsim's networks take them: times 1/255, flattened.
    std::vector<std::int64_t> dims(program.image_shape.begin(), program.image_shape.end());
    add_value_info(graph->add_input(), "observation", onnx::TensorProto::UINT8, dims);
    onnx::NodeProto* cast = g.node("Cast", {x});
    set_int_attribute(cast, "to", onnx::TensorProto::FLOAT);
    const std::string scaled = g.apply("Mul", {cast->output(0), g.scalar(1.0f / 255.0f)});
    x = g.apply("Reshape", {scaled, g.int64s({-1, program.input_size})});
  } else {
    add_value_info(graph->add_input(), "observation", onnx::TensorProto::FLOAT, {program.input_size});
  }
  for (const PolicyOp& op : program.ops) x = add_op(g, op, x);
  g.node("Identity", {x})->set_output(0, "action");
  if (program.discrete)
    add_value_info(graph->add_output(), "action", onnx::TensorProto::INT64, {});
  else
    add_value_info(graph->add_output(), "action", onnx::TensorProto::FLOAT, {program.action_size});
  try {
    onnx::checker::check_model(model);
  } catch (const std::exception& e) {
    throw Error(std::string("export: ONNX's checker refused the graph: ") + e.what());
  }
  return model.SerializeAsString();
}

}  // namespace rdsim
