#include <catch2/catch.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/nn.hpp"

using namespace rdsim;
using Eigen::MatrixXf;

TEST_CASE("save -> load gives a network with identical outputs", "[nn]") {
  Rng rng_a(1), rng_b(2);
  const nn::MlpShape shape{5, {32, 32}, 3, nn::Activation::Tanh};
  nn::Mlp a(shape, 0.01f, rng_a), b(shape, 0.01f, rng_b);
  nn::Tensor log_std_a(3, 1), log_std_b(3, 1);
  log_std_a.value << -0.5f, 0.1f, 0.3f;
  nn::ParamList pa = a.params(), pb = b.params();
  pa.push_back(nn::param_of(log_std_a, "log_std"));
  pb.push_back(nn::param_of(log_std_b, "log_std"));

  MatrixXf x(5, 4);
  for (int i = 0; i < x.size(); ++i) x.data()[i] = static_cast<float>(rng_a.normal());
  REQUIRE(a.evaluate(x) != b.evaluate(x));
  nn::params_from_bytes(pb, nn::params_to_bytes(pa), "model.bin");
  CHECK(a.evaluate(x) == b.evaluate(x));
  CHECK(log_std_b.value == log_std_a.value);
}

TEST_CASE("loading checks magic, count and shapes and leaves the network untouched", "[nn]") {
  Rng rng(4);
  nn::Mlp small({4, {8}, 2, nn::Activation::ReLU}, 1.0f, rng);
  nn::Mlp wide({4, {16}, 2, nn::Activation::ReLU}, 1.0f, rng);
  nn::Mlp deep({4, {8, 8}, 2, nn::Activation::ReLU}, 1.0f, rng);
  const std::string bytes = nn::params_to_bytes(small.params());
  const MatrixXf before = wide.layers()[1].weight.value;

  CHECK_THROWS_WITH(nn::params_from_bytes(wide.params(), bytes, "m.bin"),
                    Catch::Contains("m.bin") && Catch::Contains("layer0.weight") &&
                        Catch::Contains("8x4") && Catch::Contains("16x4"));
  CHECK(wide.layers()[1].weight.value == before);
  CHECK_THROWS_WITH(nn::params_from_bytes(deep.params(), bytes, "m.bin"), Catch::Contains("tensors"));
  CHECK_THROWS_WITH(nn::params_from_bytes(small.params(), bytes.substr(0, bytes.size() - 3), "m.bin"),
                    Catch::Contains("truncated"));
  CHECK_THROWS_WITH(nn::params_from_bytes(small.params(), "JUNKJUNKJUNK", "m.bin"), Catch::Contains("magic"));
}
