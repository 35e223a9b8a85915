// The ONNX writer (export/onnx_export.hpp) on a hand-made program holding every operation: the graph's
// interface, opset, nodes and constants as written, and ONNX's own parser reading them back. That the
// graph computes rdsim's actions is checked with onnxruntime in tests/python/test_export.py; that a
// program is the algorithm's act() in tests/algorithms/test_policy_program.cpp.
#include <catch2/catch.hpp>

#include <onnx/onnx_pb.h>

#include <vector>

#include "rdsim/export/onnx_export.hpp"

namespace {

rdsim::PolicyProgram every_op(bool discrete) {
  rdsim::PolicyProgram p;
  p.algorithm = "test";
  p.input_size = 3;
  p.discrete = discrete;
  p.action_size = discrete ? 1 : 2;
  p.standardize(Eigen::Vector3f(0.1f, 0.2f, 0.3f), Eigen::Vector3f(1.0f, 2.0f, 3.0f), 10.0f);
  p.scale(0.5f);
  rdsim::PolicyOp dense;
  dense.kind = rdsim::PolicyOp::Kind::Dense;
  dense.weight.resize(4, 3);
  dense.weight << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  dense.a = Eigen::Vector4f(0.5f, -0.5f, 1.0f, -1.0f);
  p.ops.push_back(dense);
  p.activate(rdsim::nn::Activation::Tanh);
  p.activate(rdsim::nn::Activation::ReLU);
  p.keep_rows(2);
  if (discrete) {
    p.argmax();
  } else {
    p.clip(Eigen::Vector2f(-2.0f, -1.0f), Eigen::Vector2f(2.0f, 1.0f));
    p.rescale(Eigen::Vector2f(-2.0f, -1.0f), Eigen::Vector2f(2.0f, 1.0f));
  }
  return p;
}

std::vector<std::string> op_types(const onnx::GraphProto& g) {
  std::vector<std::string> types;
  for (const auto& n : g.node()) types.push_back(n.op_type());
  return types;
}

}  // namespace

TEST_CASE("onnx export writes every policy operation as opset-13 nodes that ONNX's parser reads back", "[export]") {
  for (const bool discrete : {false, true}) {
    const std::string bytes = rdsim::onnx_model_bytes(every_op(discrete), {{"env", "test_env"}});
    onnx::ModelProto model;
    REQUIRE(model.ParseFromString(bytes));
    CHECK(model.producer_name() == "rdsim");
    REQUIRE(model.opset_import_size() == 1);
    CHECK(model.opset_import(0).version() == 13);
    REQUIRE(model.metadata_props_size() == 1);
    CHECK(model.metadata_props(0).value() == "test_env");
    const onnx::GraphProto& g = model.graph();
    REQUIRE(g.input_size() == 1);
    CHECK(g.input(0).name() == "observation");
    CHECK(g.input(0).type().tensor_type().shape().dim(1).dim_value() == 3);
    REQUIRE(g.output_size() == 1);
    CHECK(g.output(0).name() == "action");
    const std::vector<std::string> head = {"Sub", "Mul", "Clip", "Mul", "Gemm", "Tanh", "Relu", "Slice"};
    std::vector<std::string> expected = head;
    if (discrete) {
      expected.insert(expected.end(), {"ArgMax", "Identity"});
      CHECK(g.output(0).type().tensor_type().elem_type() == onnx::TensorProto::INT64);
    } else {
      expected.insert(expected.end(), {"Max", "Min", "Clip", "Add", "Mul", "Add", "Min", "Identity"});
      CHECK(g.output(0).type().tensor_type().shape().dim(1).dim_value() == 2);
    }
    CHECK(op_types(g) == expected);
    // The dense layer's weight: [out, in], row-major, used transposed by Gemm.
    const onnx::NodeProto& gemm = g.node(4);
    const onnx::TensorProto* weight = nullptr;
    for (const auto& t : g.initializer())
      if (t.name() == gemm.input(1)) weight = &t;
    REQUIRE(weight != nullptr);
    CHECK(weight->dims(0) == 4);
    CHECK(weight->dims(1) == 3);
    CHECK(weight->float_data(1) == 2.0f);
    CHECK(weight->float_data(3) == 4.0f);
    REQUIRE(gemm.attribute_size() == 1);
    CHECK(gemm.attribute(0).name() == "transB");
    CHECK(g.node(static_cast<int>(expected.size()) - 1).output(0) == "action");
  }
}
