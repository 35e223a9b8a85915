#include <catch2/catch.hpp>

#include "rdsim/core/error.hpp"
#include "gradient_check.hpp"
#include "rdsim/nn/nn.hpp"

using namespace rdsim;
using Eigen::MatrixXd;
using Eigen::MatrixXf;

namespace {

MatrixXf random_matrix(int rows, int cols, Rng& rng) {
  MatrixXf m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = static_cast<float>(rng.normal());
  return m;
}

// An independent double-precision copy of a network's weights and forward pass, so the
// finite-difference reference shares neither float rounding nor code with nn::Mlp.
struct ReferenceNet {
  std::vector<MatrixXd> tensors;  // the order of Mlp::params(): weight, bias per layer
  nn::Activation activation;

  explicit ReferenceNet(nn::Mlp& net) : activation(net.shape().activation) {
    for (const nn::Param& p : net.params()) tensors.push_back(p.value->cast<double>());
  }

  MatrixXd forward(const MatrixXd& x) const {
    MatrixXd a = x;
    const size_t layers = tensors.size() / 2;
    for (size_t i = 0; i < layers; ++i) {
      MatrixXd z = tensors[2 * i] * a;
      z.colwise() += tensors[2 * i + 1].col(0);
      if (i + 1 < layers) {
        if (activation == nn::Activation::Tanh) z = z.array().tanh();
        if (activation == nn::Activation::ReLU) z = z.cwiseMax(0.0);
      }
      a = z;
    }
    return a;
  }

  // Loss = sum(C .* output), so dLoss/dOutput = C.
  double loss(const MatrixXd& x, const MatrixXd& c) const { return forward(x).cwiseProduct(c).sum(); }
};

// Relative error with a floor, so tiny gradients are judged absolutely.
using gradcheck::rel_error;

void check_gradients(nn::Activation activation) {
  Rng rng(7);
  nn::Mlp net({3, {5, 4}, 2, activation}, 1.0f, rng);
  // Non-zero biases so the ReLU kinks are not all at the same place.
  for (auto& layer : net.layers()) layer.bias.value = 0.3f * random_matrix(layer.out_size(), 1, rng);
  const MatrixXf x = random_matrix(3, 6, rng);
  const MatrixXf c = random_matrix(2, 6, rng);
  ReferenceNet ref(net);
  const MatrixXd xd = x.cast<double>(), cd = c.cast<double>();

  const MatrixXf out = net.forward(x);
  REQUIRE(out.isApprox(ref.forward(xd).cast<float>(), 1e-5f));
  net.zero_grad();
  const MatrixXf grad_x = net.backward(c);

  gradcheck::check(ref, xd, cd, grad_x, net.params());
}

}  // namespace

TEST_CASE("Mlp gradients match finite differences (tanh)", "[nn]") { check_gradients(nn::Activation::Tanh); }
TEST_CASE("Mlp gradients match finite differences (relu)", "[nn]") { check_gradients(nn::Activation::ReLU); }

TEST_CASE("Mlp backward accumulates and zero_grad clears", "[nn]") {
  Rng rng(3);
  nn::Mlp net({4, {8}, 3, nn::Activation::Tanh}, 1.0f, rng);
  const MatrixXf x = random_matrix(4, 5, rng), c = random_matrix(3, 5, rng);
  net.forward(x);
  net.zero_grad();
  net.backward(c, false);
  std::vector<MatrixXf> once;
  for (const nn::Param& p : net.params()) once.push_back(*p.grad);
  net.backward(c, false);
  const nn::ParamList params = net.params();
  for (size_t i = 0; i < params.size(); ++i) {
    INFO(params[i].name);
    REQUIRE(once[i].norm() > 0.0f);
    CHECK(params[i].grad->isApprox(2.0f * once[i]));
  }
  net.zero_grad();
  CHECK(nn::global_grad_norm(params) == 0.0f);
}

TEST_CASE("Mlp input_gradient is backward's input gradient and leaves the parameter gradients alone", "[nn]") {
  Rng rng(5);
  // 128 x 128 on 256 columns: the layer whose two backward products run side by side.
  nn::Mlp net({12, {128, 128}, 1, nn::Activation::ReLU}, 1.0f, rng);
  const MatrixXf x = random_matrix(12, 256, rng), c = random_matrix(1, 256, rng);
  net.forward(x);
  net.zero_grad();
  const MatrixXf through = net.input_gradient(c);
  CHECK(nn::global_grad_norm(net.params()) == 0.0f);
  const MatrixXf full = net.backward(c);
  CHECK(through == full);  // the same products in the same order: the same bits
  CHECK_THROWS_WITH(net.input_gradient(MatrixXf::Ones(1, 3)), Catch::Contains("does not match"));
}

TEST_CASE("Mlp backward gives the same bits on one thread and on two", "[nn]") {
  std::vector<nn::GemmBackend> backends = {nn::GemmBackend::Eigen};
  if (nn::onednn_available()) backends.push_back(nn::GemmBackend::OneDnn);
  for (const nn::GemmBackend backend : backends) {
    std::vector<MatrixXf> results[2];
    for (int threads : {1, 2}) {
      const nn::GemmScope scope(backend, threads);
      Rng rng(8);
      nn::Mlp net({12, {128, 128}, 3, nn::Activation::Tanh}, 1.0f, rng);
      const MatrixXf x = random_matrix(12, 256, rng), c = random_matrix(3, 256, rng);
      net.forward(x);
      net.zero_grad();
      results[threads - 1].push_back(net.backward(c));
      for (const nn::Param& p : net.params()) results[threads - 1].push_back(*p.grad);
    }
    REQUIRE(results[0].size() == results[1].size());
    for (size_t i = 0; i < results[0].size(); ++i) CHECK(results[0][i] == results[1][i]);
  }
}

TEST_CASE("Mlp infer and evaluate agree with forward and keep the training cache", "[nn]") {
  Rng rng(11);
  nn::Mlp net({4, {16, 16}, 2, nn::Activation::ReLU}, 0.01f, rng);
  const MatrixXf batch = random_matrix(4, 7, rng);
  const MatrixXf trained = net.forward(batch);
  const MatrixXf one = net.infer(batch.col(2));
  CHECK(one.isApprox(trained.col(2)));
  CHECK(net.evaluate(batch).isApprox(trained));
  // backward after infer() still uses the forward() batch of 7 columns.
  net.zero_grad();
  CHECK(net.backward(MatrixXf::Ones(2, 7)).cols() == 7);
}

TEST_CASE("Orthogonal init gives orthonormal rows/columns scaled by the gain", "[nn]") {
  Rng rng(5);
  for (auto [rows, cols] : {std::pair{64, 64}, std::pair{64, 4}, std::pair{2, 64}}) {
    MatrixXf w(rows, cols);
    nn::orthogonal_init(w, 1.5f, rng);
    const MatrixXf gram = rows >= cols ? MatrixXf(w.transpose() * w) : MatrixXf(w * w.transpose());
    const int n = std::min(rows, cols);
    CHECK((gram - 2.25f * MatrixXf::Identity(n, n)).cwiseAbs().maxCoeff() < 1e-4f);
  }
  Rng a(9), b(9);
  MatrixXf wa(8, 3), wb(8, 3);
  nn::orthogonal_init(wa, 1.0f, a);
  nn::orthogonal_init(wb, 1.0f, b);
  CHECK(wa == wb);
}

TEST_CASE("Mlp layers use the hidden and output gains", "[nn]") {
  Rng rng(1);
  nn::Mlp net({4, {64, 64}, 2, nn::Activation::Tanh}, 0.01f, rng);
  const auto& layers = net.layers();
  REQUIRE(layers.size() == 3);
  const MatrixXf w0 = layers[0].weight.value;  // 64 x 4: orthonormal columns * sqrt(2)
  CHECK((w0.transpose() * w0 - 2.0f * MatrixXf::Identity(4, 4)).cwiseAbs().maxCoeff() < 1e-4f);
  const MatrixXf w2 = layers[2].weight.value;  // 2 x 64: orthonormal rows * 0.01
  CHECK((w2 * w2.transpose() - 1e-4f * MatrixXf::Identity(2, 2)).cwiseAbs().maxCoeff() < 1e-7f);
  CHECK(layers[1].bias.value.norm() == 0.0f);
  CHECK(nn::parameter_count(net.params()) == 4 * 64 + 64 + 64 * 64 + 64 + 64 * 2 + 2);
}

TEST_CASE("Mlp rejects bad shapes and activation names", "[nn]") {
  Rng rng(1);
  CHECK_THROWS_AS(nn::Mlp({0, {4}, 2, nn::Activation::Tanh}, 1.0f, rng), Error);
  CHECK_THROWS_AS(nn::Mlp({3, {0}, 2, nn::Activation::Tanh}, 1.0f, rng), Error);
  nn::Mlp net({3, {4}, 2, nn::Activation::Tanh}, 1.0f, rng);
  CHECK_THROWS_AS(net.forward(MatrixXf::Zero(4, 1)), Error);
  CHECK(nn::activation_from_string("relu", "x") == nn::Activation::ReLU);
  CHECK_THROWS_WITH(nn::activation_from_string("sigmoid", "cfg.json: network.activation"),
                    Catch::Contains("cfg.json: network.activation") && Catch::Contains("sigmoid"));
}

TEST_CASE("copy_values_from and blend_values_from", "[nn]") {
  Rng rng(2);
  nn::Mlp a({3, {4}, 2, nn::Activation::ReLU}, 1.0f, rng);
  nn::Mlp b({3, {4}, 2, nn::Activation::ReLU}, 1.0f, rng);
  const MatrixXf x = random_matrix(3, 4, rng);
  nn::Mlp c = b;
  c.blend_values_from(a, 0.25f);
  CHECK(c.layers()[0].weight.value.isApprox(0.25f * a.layers()[0].weight.value + 0.75f * b.layers()[0].weight.value));
  b.copy_values_from(a);
  CHECK(b.evaluate(x) == a.evaluate(x));
  nn::Mlp other({3, {5}, 2, nn::Activation::ReLU}, 1.0f, rng);
  CHECK_THROWS_AS(b.copy_values_from(other), Error);
}

TEST_CASE("Mlp jvp is the directional derivative of the output along a parameter direction", "[nn]") {
  for (auto activation : {nn::Activation::Tanh, nn::Activation::ReLU}) {
    Rng rng(21);
    nn::Mlp net({3, {6, 5}, 2, activation}, 1.0f, rng);
    for (auto& layer : net.layers()) layer.bias.value = 0.3f * random_matrix(layer.out_size(), 1, rng);
    const MatrixXf x = random_matrix(3, 4, rng);
    const nn::ParamList params = net.params();
    const Eigen::VectorXf theta = nn::flatten_values(params);
    const Eigen::VectorXf dir = random_matrix(static_cast<int>(theta.size()), 1, rng);
    // A double reference: d/de net_{theta + e dir}(x) by central differences.
    ReferenceNet ref(net);
    const double h = 1e-6;
    const auto shifted = [&](double e) {
      ReferenceNet r = ref;
      Eigen::Index at = 0;
      for (auto& t : r.tensors) {
        t += e * Eigen::Map<const Eigen::MatrixXf>(dir.data() + at, t.rows(), t.cols()).cast<double>();
        at += t.size();
      }
      return r.forward(x.cast<double>());
    };
    const MatrixXd numeric = (shifted(h) - shifted(-h)) / (2 * h);
    net.forward(x);
    const MatrixXf jvp = net.jvp(dir);
    CHECK((jvp.cast<double>() - numeric).cwiseAbs().maxCoeff() < 1e-4 * std::max(1.0, numeric.cwiseAbs().maxCoeff()));
    CHECK_THROWS_AS(net.jvp(dir.head(3)), Error);
  }
}

TEST_CASE("parameters flatten to one vector and back", "[nn]") {
  Rng rng(22);
  nn::Mlp net({2, {3}, 2, nn::Activation::Tanh}, 1.0f, rng);
  const nn::ParamList params = net.params();
  const Eigen::VectorXf flat = nn::flatten_values(params);
  CHECK(flat.size() == nn::parameter_count(params));
  CHECK(flat[0] == (*params[0].value)(0, 0));
  CHECK(flat[1] == (*params[0].value)(1, 0));  // column-major within a tensor
  CHECK(flat[6] == (*params[1].value)(0, 0));  // then the next tensor
  nn::assign_values(params, 2.0f * flat);
  CHECK(nn::flatten_values(params) == 2.0f * flat);
  for (const auto& p : params) p.grad->setConstant(0.5f);
  CHECK(nn::flatten_grads(params) == Eigen::VectorXf::Constant(flat.size(), 0.5f));
  CHECK_THROWS_AS(nn::assign_values(params, flat.head(4)), Error);
}
