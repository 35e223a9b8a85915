// rdsim_policy on its own (this program links nothing else of rdsim but core and nn): the policy
// part of a model file read back into a Policy that acts as its program does, and every kind of
// damaged or unusable file refused with one clear error. The policies of trained models are
// checked against their algorithms in tests/algorithms (test_policy_program) and, through
// `rdsim train`, in tests/app (test_policy_cli).
#include <catch2/catch.hpp>
#include <cstring>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/model_envelope.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/nn/mlp.hpp"
#include "rdsim/policy/policy.hpp"
#include "rdsim/policy/policy_file.hpp"

using Catch::Matchers::Contains;

namespace {

// A Gaussian-mean policy on 5 values: standardize, tanh MLP, clip to [-1, 2].
rdsim::PolicyProgram box_program() {
  rdsim::Rng rng(4);
  rdsim::nn::Mlp net(rdsim::nn::MlpShape{5, {8, 8}, 3, rdsim::nn::Activation::Tanh}, 1.0f, rng);
  rdsim::PolicyProgram p;
  p.algorithm = "ppo";
  p.input_size = 5;
  p.action_size = 3;
  p.standardize(Eigen::VectorXf::Constant(5, 0.5f), Eigen::VectorXf::Constant(5, 2.0f), 10.0f);
  p.mlp(net);
  p.clip(Eigen::VectorXf::Constant(3, -1.0f), Eigen::VectorXf::Constant(3, 2.0f));
  return p;
}

// A discrete policy on 6x5x3 images: one conv, a dense head, argmax.
rdsim::PolicyProgram image_program() {
  rdsim::Rng rng(5);
  rdsim::nn::CnnShape shape;
  shape.input = {6, 5, 3};
  shape.convs = {{4, 3, 1, 1}};
  shape.hidden_sizes = {8};
  shape.output_size = 4;
  rdsim::nn::Cnn net(shape, 1.0f, rng);
  rdsim::PolicyProgram p;
  p.algorithm = "dqn";
  p.input_size = 90;
  p.pixels = true;
  p.image_shape = {6, 5, 3};
  p.discrete = true;
  p.action_size = 1;
  p.cnn(net);
  p.argmax();
  return p;
}

std::string model_bytes(const std::string& policy, std::uint32_t kind = 0) {
  return rdsim::encode_model_envelope({.kind = kind, .config = "{}", .spec = "toy: observation float32 {5}, actions box 3",
                                       .payload = "weights", .policy = policy});
}

// A version 3 file (before the policy part): the same envelope without it.
std::string version3_bytes() {
  std::string out = "RDSIMMDL";
  const auto put32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  const auto block = [&](const std::string& b) {
    const std::uint64_t n = b.size();
    out.append(reinterpret_cast<const char*>(&n), 8);
    out += b;
  };
  put32(3);
  put32(0);
  block("{}");
  block("toy");
  block("weights");
  const std::uint64_t sum = rdsim::fnv1a64(out);
  out.append(reinterpret_cast<const char*>(&sum), 8);
  return out;
}

}  // namespace

TEST_CASE("policy: a model file's policy acts as its program", "[policy]") {
  const rdsim::PolicyProgram program = box_program();
  const rdsim::Policy policy = rdsim::Policy::from_bytes(model_bytes(rdsim::encode_policy_program(program)), "model.bin");
  CHECK(policy.algorithm() == "ppo");
  CHECK(policy.env_spec() == "toy: observation float32 {5}, actions box 3");
  CHECK_FALSE(policy.discrete());
  CHECK(policy.action_size() == 3);
  CHECK(policy.observation_space().shape == std::vector<int>{5});
  rdsim::Rng rng(6);
  Eigen::MatrixXf x(5, 200);
  for (Eigen::Index k = 0; k < x.size(); ++k) x.data()[k] = static_cast<float>(3.0 * rng.normal());
  CHECK(policy.act_batch(x) == rdsim::run_policy_program(program, x));
  for (int i = 0; i < 200; ++i) {
    const std::vector<float> obs(x.col(i).data(), x.col(i).data() + 5);
    const rdsim::Action a = policy.act(obs);
    REQUIRE(a.values.size() == 3);
    // One observation alone, as the program computes it (a batch may round differently).
    CHECK(a.values == rdsim::run_policy_program(program, x.col(i)).col(0));
    CHECK(a.values.maxCoeff() <= 2.0f);
    CHECK(a.values.minCoeff() >= -1.0f);
  }
}

TEST_CASE("policy: image policies take the env's uint8 images", "[policy]") {
  const rdsim::PolicyProgram program = image_program();
  const rdsim::Policy policy = rdsim::Policy::from_bytes(model_bytes(rdsim::encode_policy_program(program)), "model.bin");
  CHECK(policy.discrete());
  CHECK(policy.observation_space().type == rdsim::ObsType::UInt8);
  rdsim::Rng rng(7);
  int seen[4] = {};
  for (int i = 0; i < 100; ++i) {
    std::vector<std::uint8_t> image(90);
    for (auto& p : image) p = static_cast<std::uint8_t>(rng.below(256));
    Eigen::MatrixXf x(90, 1);
    for (int k = 0; k < 90; ++k) x(k, 0) = static_cast<float>(image[static_cast<std::size_t>(k)]) / 255.0f;
    const int expected = static_cast<int>(rdsim::run_policy_program(program, x)(0, 0));
    const int got = policy.act(std::span<const std::uint8_t>(image)).index;
    CHECK(got == expected);
    ++seen[got];
  }
  CHECK_THROWS_WITH(policy.act(std::vector<float>(90, 0.0f)), Contains("takes uint8 images"));
}

TEST_CASE("policy: observations of the wrong size or type are one clear error", "[policy]") {
  const rdsim::Policy policy =
      rdsim::Policy::from_bytes(model_bytes(rdsim::encode_policy_program(box_program())), "model.bin");
  CHECK_THROWS_WITH(policy.act(std::vector<float>(4, 0.0f)), Contains("observation has 4 values") && Contains("says 5"));
  CHECK_THROWS_WITH(policy.act(std::vector<std::uint8_t>(5, 0)), Contains("takes float values"));
  CHECK_THROWS_WITH(policy.act_batch(Eigen::MatrixXf::Zero(6, 2)), Contains("6 values each") && Contains("takes 5"));
}

TEST_CASE("policy: files without a usable policy are one clear error", "[policy]") {
  CHECK_THROWS_WITH(rdsim::Policy::from_bytes(version3_bytes(), "old.bin"), Contains("old.bin: has no policy part"));
  CHECK_THROWS_WITH(rdsim::Policy::from_bytes(model_bytes(""), "random.bin"), Contains("random.bin: has no policy part"));
  CHECK_THROWS_WITH(rdsim::Policy::from_bytes("not a model", "x.bin"), Contains("x.bin: not an rdsim model file"));
  CHECK_THROWS_WITH(rdsim::Policy::load("/nonexistent/model.bin"), Contains("/nonexistent/model.bin"));
}

TEST_CASE("policy: every truncation and many flipped bytes of a policy are clear errors, never a crash", "[policy]") {
  for (const rdsim::PolicyProgram& program : {box_program(), image_program()}) {
    const std::string bytes = rdsim::encode_policy_program(program);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      INFO(n);
      CHECK_THROWS_AS(rdsim::decode_policy_program(bytes.substr(0, n), "p"), rdsim::Error);
    }
    CHECK_THROWS_WITH(rdsim::decode_policy_program(bytes + "x", "p"), Contains("unexpected bytes"));
    rdsim::Rng rng(8);
    int refused = 0;
    for (int k = 0; k < 2000; ++k) {  // a flipped byte decodes to a valid policy or is refused
      std::string damaged = bytes;
      damaged[static_cast<std::size_t>(rng.below(bytes.size()))] ^= static_cast<char>(1 + rng.below(255));
      try {
        const rdsim::PolicyProgram p = rdsim::decode_policy_program(damaged, "p");
        Eigen::MatrixXf x = Eigen::MatrixXf::Zero(p.input_size, 2);
        const Eigen::MatrixXf y = rdsim::run_policy_program(p, x);
        CHECK(y.rows() == (p.discrete ? 1 : p.action_size));
      } catch (const rdsim::Error& e) {
        CHECK(std::string(e.what()).rfind("p: ", 0) == 0);
        ++refused;
      }
    }
    CHECK(refused > 0);
  }
}

TEST_CASE("policy: a damaged policy names what is wrong", "[policy]") {
  rdsim::PolicyProgram p = box_program();
  p.ops[1].weight(0, 0) = std::nanf("");
  CHECK_THROWS_WITH(rdsim::decode_policy_program(rdsim::encode_policy_program(p), "m.bin"), Contains("not finite"));
  p = box_program();
  p.action_size = 4;  // the last op leaves 3
  CHECK_THROWS_WITH(rdsim::decode_policy_program(rdsim::encode_policy_program(p), "m.bin"),
                    Contains("m.bin: policy is damaged: its last operation leaves 3 values per observation, expected 4"));
  p = box_program();
  p.ops.back().a(0) = 5.0f;  // clip low above high
  CHECK_THROWS_WITH(rdsim::decode_policy_program(rdsim::encode_policy_program(p), "m.bin"), Contains("low bound above"));
  p = image_program();
  p.discrete = false;
  CHECK_THROWS_WITH(rdsim::decode_policy_program(rdsim::encode_policy_program(p), "m.bin"), Contains("argmax"));
}
