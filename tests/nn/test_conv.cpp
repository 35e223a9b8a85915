#include <catch2/catch.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/nn/conv.hpp"
#include "rdsim/nn/nn.hpp"
#include "gradient_check.hpp"

using namespace rdsim;
using Eigen::MatrixXd;
using Eigen::MatrixXf;

namespace {

MatrixXf random_matrix(int rows, int cols, Rng& rng, double scale = 1.0) {
  MatrixXf m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = static_cast<float>(scale * rng.normal());
  return m;
}

// Direct definition of the convolution in double precision (HWC images, one per column, weight
// column (ky * k + kx) * C + c), sharing no code or rounding with nn::Conv2d.
MatrixXd reference_conv(const MatrixXd& x, const MatrixXd& w, const MatrixXd& b, const nn::ImageShape& in,
                        const nn::ConvSpec& s) {
  const int oh = (in.height + 2 * s.padding - s.kernel) / s.stride + 1;
  const int ow = (in.width + 2 * s.padding - s.kernel) / s.stride + 1;
  MatrixXd y(oh * ow * s.out_channels, x.cols());
  for (int n = 0; n < x.cols(); ++n)
    for (int oy = 0; oy < oh; ++oy)
      for (int ox = 0; ox < ow; ++ox)
        for (int co = 0; co < s.out_channels; ++co) {
          double sum = b(co, 0);
          for (int ky = 0; ky < s.kernel; ++ky)
            for (int kx = 0; kx < s.kernel; ++kx) {
              const int iy = oy * s.stride - s.padding + ky, ix = ox * s.stride - s.padding + kx;
              if (iy < 0 || iy >= in.height || ix < 0 || ix >= in.width) continue;
              for (int c = 0; c < in.channels; ++c)
                sum += w(co, (ky * s.kernel + kx) * in.channels + c) * x((iy * in.width + ix) * in.channels + c, n);
            }
          y((oy * ow + ox) * s.out_channels + co, n) = sum;
        }
  return y;
}

MatrixXd reference_activate(MatrixXd z, nn::Activation a) {
  if (a == nn::Activation::ReLU) return z.cwiseMax(0.0);
  if (a == nn::Activation::Tanh) return z.array().tanh();
  return z;
}

// A double-precision copy of a Cnn (tensors in params() order) with its own forward pass.
struct ReferenceCnn {
  nn::CnnShape shape;
  std::vector<MatrixXd> tensors;

  explicit ReferenceCnn(nn::Cnn& net) : shape(net.shape()) {
    for (const nn::Param& p : net.params()) tensors.push_back(p.value->cast<double>());
  }

  MatrixXd forward(const MatrixXd& x) const {
    MatrixXd a = x;
    nn::ImageShape image = shape.input;
    size_t t = 0;
    for (const nn::ConvSpec& s : shape.convs) {
      a = reference_activate(reference_conv(a, tensors[t], tensors[t + 1], image, s), shape.activation);
      image = {(image.height + 2 * s.padding - s.kernel) / s.stride + 1,
               (image.width + 2 * s.padding - s.kernel) / s.stride + 1, s.out_channels};
      t += 2;
    }
    for (; t < tensors.size(); t += 2) {
      MatrixXd z = tensors[t] * a;
      z.colwise() += tensors[t + 1].col(0);
      a = t + 2 < tensors.size() ? reference_activate(z, shape.activation) : z;
    }
    return a;
  }

  // Loss = sum(C .* output), so dLoss/dOutput = C.
  double loss(const MatrixXd& x, const MatrixXd& c) const { return forward(x).cwiseProduct(c).sum(); }
};

// Relative error with a floor, so tiny gradients are judged absolutely.
using gradcheck::rel_error;

// Central differences of the double reference against the analytic float gradients of `net`
// for the loss sum(C .* net(x)).
void check_cnn_gradients(nn::Cnn& net, const MatrixXf& x, const MatrixXf& c) {
  ReferenceCnn ref(net);
  const MatrixXd xd = x.cast<double>(), cd = c.cast<double>();
  REQUIRE(net.forward(x).isApprox(ref.forward(xd).cast<float>(), 1e-5f));
  net.zero_grad();
  const MatrixXf grad_x = net.backward(c);
  REQUIRE(grad_x.rows() == x.rows());
  REQUIRE(grad_x.cols() == x.cols());

  gradcheck::check(ref, xd, cd, grad_x, net.params());
}

}  // namespace

TEST_CASE("Conv2d computes a hand-worked convolution in HWC layout", "[nn][conv]") {
  Rng rng(1);
  nn::Conv2d conv({3, 3, 1}, {2, 2, 1, 0}, 1.0f, rng);
  REQUIRE(conv.output == nn::ImageShape{2, 2, 2});
  // Channel 0: kernel [[1 2] [3 4]], bias 0.5. Channel 1 picks the bottom-right pixel.
  conv.weight.value << 1, 2, 3, 4,
                       0, 0, 0, 1;
  conv.bias.value << 0.5f, 0.0f;
  MatrixXf x(9, 1);
  x << 1, 2, 3, 4, 5, 6, 7, 8, 9;  // [[1 2 3] [4 5 6] [7 8 9]]
  nn::ConvWorkspace ws;
  MatrixXf y;
  conv.forward(x, y, ws);
  MatrixXf expected(8, 1);
  // (1*1 + 2*2 + 4*3 + 5*4) + 0.5 = 37.5 at (0,0), then channel 1 = x(1,1) = 5, and so on.
  expected << 37.5f, 5, 47.5f, 6, 67.5f, 8, 77.5f, 9;
  CHECK(y == expected);

  // Stride 2, padding 1: the kernel hangs over the zero border.
  nn::Conv2d padded({3, 3, 1}, {1, 2, 2, 1}, 1.0f, rng);
  REQUIRE(padded.output == nn::ImageShape{2, 2, 1});
  padded.weight.value << 1, 2, 3, 4;
  padded.bias.value << 0.0f;
  padded.forward(x, y, ws);
  // (0,0) sees only x(0,0) under k(1,1): 4; (0,1): 3*2 + 4*3; (1,0): 2*4 + 4*7; (1,1): 5+12+24+36.
  expected.resize(4, 1);
  expected << 4, 18, 36, 77;
  CHECK(y == expected);
}

TEST_CASE("Conv2d gradients (stride 2, padding 1) match finite differences", "[nn][conv]") {
  Rng rng(3);
  const nn::ImageShape in{7, 6, 2};
  const nn::ConvSpec spec{3, 3, 2, 1};
  nn::Conv2d conv(in, spec, 1.41421356f, rng);
  REQUIRE(conv.output == nn::ImageShape{4, 3, 3});
  conv.bias.value = random_matrix(3, 1, rng, 0.3);
  const MatrixXf x = random_matrix(in.size(), 3, rng);
  const MatrixXf c = random_matrix(conv.out_size(), 3, rng);

  MatrixXd w = conv.weight.value.cast<double>(), b = conv.bias.value.cast<double>();
  const MatrixXd xd = x.cast<double>(), cd = c.cast<double>();
  auto loss = [&](const MatrixXd& xx) { return reference_conv(xx, w, b, in, spec).cwiseProduct(cd).sum(); };

  nn::ConvWorkspace ws;
  MatrixXf y, grad_x;
  conv.forward(x, y, ws);
  REQUIRE(y.isApprox(reference_conv(xd, w, b, in, spec).cast<float>(), 1e-5f));
  conv.weight.zero_grad();
  conv.bias.zero_grad();
  conv.backward(x, c, &grad_x, ws);

  const double h = 1e-6;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    MatrixXd xp = xd, xm = xd;
    xp.data()[k] += h;
    xm.data()[k] -= h;
    INFO("input[" << k << "]");
    CHECK(rel_error(grad_x.data()[k], (loss(xp) - loss(xm)) / (2 * h)) < 1e-4);
  }
  for (MatrixXd* p : {&w, &b}) {
    const MatrixXf& analytic = p == &w ? conv.weight.grad : conv.bias.grad;
    for (Eigen::Index k = 0; k < p->size(); ++k) {
      const double saved = p->data()[k];
      p->data()[k] = saved + h;
      const double lp = loss(xd);
      p->data()[k] = saved - h;
      const double lm = loss(xd);
      p->data()[k] = saved;
      INFO((p == &w ? "weight[" : "bias[") << k << "]");
      CHECK(rel_error(analytic.data()[k], (lp - lm) / (2 * h)) < 1e-4);
    }
  }
}

TEST_CASE("Conv2d gives the same results whatever the chunking, and accumulates", "[nn][conv]") {
  Rng rng(4);
  nn::Conv2d conv({9, 9, 3}, {4, 3, 2, 1}, 1.41421356f, rng);
  const MatrixXf x = random_matrix(conv.in_size(), 5, rng);
  const MatrixXf c = random_matrix(conv.out_size(), 5, rng);
  nn::ConvWorkspace whole, per_sample, uneven;
  per_sample.max_patch_floats = 1;                                          // one sample a chunk
  uneven.max_patch_floats = 2LL * conv.patch_size() * 5 * 5;                // chunks of 2, 2, 1
  MatrixXf y_whole, y_one, y_uneven, gx_whole, gx_one;
  conv.forward(x, y_whole, whole);
  conv.forward(x, y_one, per_sample);
  conv.forward(x, y_uneven, uneven);
  CHECK(y_one.isApprox(y_whole, 1e-6f));
  CHECK(y_uneven.isApprox(y_whole, 1e-6f));

  conv.weight.zero_grad();
  conv.bias.zero_grad();
  conv.backward(x, c, &gx_whole, whole);
  const MatrixXf gw = conv.weight.grad, gb = conv.bias.grad;
  REQUIRE(gw.norm() > 0.0f);
  conv.backward(x, c, &gx_one, per_sample);  // accumulates: now twice the gradient
  CHECK(gx_one.isApprox(gx_whole, 1e-6f));
  CHECK(conv.weight.grad.isApprox(2.0f * gw, 1e-5f));
  CHECK(conv.bias.grad.isApprox(2.0f * gb, 1e-5f));

  CHECK_THROWS_AS(conv.forward(MatrixXf::Zero(5, 1), y_whole, whole), Error);
  CHECK_THROWS_AS(conv.backward(x, MatrixXf::Zero(conv.out_size(), 4), nullptr, whole), Error);
}

TEST_CASE("Conv2d init: orthogonal rows scaled by sqrt(2), zero bias", "[nn][conv]") {
  Rng rng(5);
  nn::Conv2d conv({84, 84, 4}, {32, 8, 4, 0}, 1.41421356f, rng);
  const MatrixXf& w = conv.weight.value;  // 32 x 256
  REQUIRE(w.rows() == 32);
  REQUIRE(w.cols() == 256);
  CHECK((w * w.transpose() - 2.0f * MatrixXf::Identity(32, 32)).cwiseAbs().maxCoeff() < 1e-4f);
  CHECK(conv.bias.value.norm() == 0.0f);
}

TEST_CASE("Cnn gradients match finite differences end to end", "[nn][cnn]") {
  for (nn::Activation activation : {nn::Activation::ReLU, nn::Activation::Tanh}) {
    INFO(nn::to_string(activation));
    Rng rng(6);
    const nn::CnnShape shape{{9, 8, 2}, {{4, 3, 2, 1}, {3, 2, 1, 0}}, {5}, 2, activation};
    nn::Cnn net(shape, 1.0f, rng);
    // Non-zero biases so the ReLU kinks are not all at the same place.
    for (const nn::Param& p : net.params())
      if (p.value->cols() == 1) *p.value = random_matrix(static_cast<int>(p.value->rows()), 1, rng, 0.3);
    const MatrixXf x = random_matrix(net.input_size(), 3, rng);
    const MatrixXf c = random_matrix(2, 3, rng);
    check_cnn_gradients(net, x, c);
  }
}

TEST_CASE("Cnn presets: shapes of the Nature and small networks", "[nn][cnn]") {
  Rng rng(7);
  nn::CnnShape shape = nn::nature_cnn({84, 84, 3}, 6);
  CHECK(shape.hidden_sizes == std::vector<int>{512});
  // Used as a feature trunk (no hidden dense layer): the orthogonal init of the 3136 x 512
  // layer alone takes over a second, and the conv stack is what is being checked here.
  shape.hidden_sizes.clear();
  nn::Cnn nature(shape, 0.01f, rng);
  REQUIRE(nature.convs().size() == 3);
  CHECK(nature.convs()[0].output == nn::ImageShape{20, 20, 32});
  CHECK(nature.convs()[1].output == nn::ImageShape{9, 9, 64});
  CHECK(nature.convs()[2].output == nn::ImageShape{7, 7, 64});
  CHECK(nature.feature_size() == 7 * 7 * 64);
  CHECK(nn::parameter_count(nature.params()) ==
        (32 * 8 * 8 * 3 + 32) + (64 * 4 * 4 * 32 + 64) + (64 * 3 * 3 * 64 + 64) + (3136 * 6 + 6));
  const MatrixXf out = nature.forward(random_matrix(84 * 84 * 3, 2, rng));
  CHECK(out.rows() == 6);
  CHECK(out.cols() == 2);

  CHECK(nn::conv_output_shape({224, 224, 3}, {32, 8, 4, 0}, "x") == nn::ImageShape{55, 55, 32});
  Rng rng2(7);
  nn::Cnn small(nn::cnn_preset("small", {64, 64, 6}, 4, "cfg.json: network.cnn"), 1.0f, rng2);
  CHECK(small.convs()[0].output == nn::ImageShape{15, 15, 16});
  CHECK(small.feature_size() == 6 * 6 * 32);
  CHECK(small.input_size() == 64 * 64 * 6);
  CHECK(small.output_size() == 4);
  CHECK(small.head().layers().size() == 2);
  CHECK(small.head().layers()[0].out_size() == 256);
}

TEST_CASE("Cnn infer and evaluate agree with forward, backward accumulates", "[nn][cnn]") {
  Rng rng(8);
  nn::Cnn net(nn::small_cnn({32, 32, 3}, 3), 1.0f, rng);
  const MatrixXf batch = random_matrix(net.input_size(), 4, rng, 0.5);
  const MatrixXf c = random_matrix(3, 4, rng);
  const MatrixXf trained = net.forward(batch);
  CHECK(net.infer(batch.col(1)).isApprox(trained.col(1), 1e-5f));
  CHECK(net.evaluate(batch).isApprox(trained, 1e-5f));
  net.zero_grad();
  CHECK(net.backward(c, false).size() == 0);  // after infer(): still the forward() batch
  std::vector<MatrixXf> once;
  for (const nn::Param& p : net.params()) once.push_back(*p.grad);
  net.backward(c, false);
  const nn::ParamList params = net.params();
  for (size_t i = 0; i < params.size(); ++i) {
    INFO(params[i].name);
    REQUIRE(once[i].norm() > 0.0f);
    CHECK(params[i].grad->isApprox(2.0f * once[i], 1e-5f));
  }
  net.zero_grad();
  CHECK(nn::global_grad_norm(params) == 0.0f);
  CHECK_THROWS_AS(net.backward(MatrixXf::Zero(3, 2)), Error);
}

TEST_CASE("Cnn save -> load gives identical outputs, shapes are checked", "[nn][cnn]") {
  Rng rng_a(1), rng_b(2);
  const nn::CnnShape shape = nn::small_cnn({36, 36, 3}, 4);
  nn::Cnn a(shape, 1.0f, rng_a), b(shape, 1.0f, rng_b);
  const MatrixXf x = random_matrix(a.input_size(), 3, rng_a, 0.5);
  REQUIRE(a.evaluate(x) != b.evaluate(x));
  const std::string bytes = nn::params_to_bytes(a.params());
  nn::params_from_bytes(b.params(), bytes, "model.bin");
  CHECK(a.evaluate(x) == b.evaluate(x));

  nn::Cnn deeper(nn::nature_cnn({36, 36, 3}, 4), 1.0f, rng_b);
  CHECK_THROWS_WITH(nn::params_from_bytes(deeper.params(), bytes, "model.bin"), Catch::Contains("tensors"));
  CHECK_THROWS_AS(b.copy_values_from(deeper), Error);
  nn::Cnn stacked(nn::small_cnn({36, 36, 6}, 4), 1.0f, rng_b);  // two cameras: 6 channels
  CHECK_THROWS_WITH(nn::params_from_bytes(stacked.params(), bytes, "model.bin"),
                    Catch::Contains("model.bin") && Catch::Contains("conv0.weight") && Catch::Contains("16x384"));
  CHECK_THROWS_AS(b.copy_values_from(stacked), Error);

  nn::Cnn c(shape, 1.0f, rng_b);
  const MatrixXf before = c.convs()[1].weight.value;
  c.blend_values_from(a, 0.25f);
  CHECK(c.convs()[1].weight.value.isApprox(0.25f * a.convs()[1].weight.value + 0.75f * before));
  c.copy_values_from(a);
  CHECK(c.evaluate(x) == a.evaluate(x));
}

TEST_CASE("Cnn rejects bad shapes with messages naming the layer", "[nn][cnn]") {
  Rng rng(9);
  CHECK_THROWS_WITH(nn::Cnn(nn::nature_cnn({30, 30, 3}, 2), 1.0f, rng),
                    Catch::Contains("conv2") && Catch::Contains("does not fit") && Catch::Contains("2x2x64"));
  CHECK_THROWS_AS(nn::Cnn(nn::small_cnn({64, 64, 0}, 2), 1.0f, rng), Error);
  CHECK_THROWS_AS(nn::Cnn(nn::small_cnn({64, 64, 3}, 0), 1.0f, rng), Error);
  CHECK_THROWS_AS(nn::Cnn({{16, 16, 1}, {{8, 3, 0, 0}}, {}, 2}, 1.0f, rng), Error);  // stride 0
  CHECK_THROWS_WITH(nn::cnn_preset("resnet", {64, 64, 3}, 2, "cfg.json: network.cnn"),
                    Catch::Contains("cfg.json: network.cnn") && Catch::Contains("resnet"));
  nn::Cnn net(nn::small_cnn({64, 64, 3}, 2), 1.0f, rng);
  CHECK_THROWS_WITH(net.forward(MatrixXf::Zero(100, 1)), Catch::Contains("64x64x3"));
}
