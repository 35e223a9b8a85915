#include <catch2/catch.hpp>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/serialize.hpp"
#include "rdsim/nn/nn.hpp"

using namespace rdsim;
using Eigen::MatrixXf;

namespace {

// f(x) = 0.5 * sum a_i (x_i - c_i)^2 with very different curvatures a_i.
struct Quadratic {
  MatrixXf a{MatrixXf(3, 2)}, c{MatrixXf(3, 2)};
  Quadratic() {
    a << 1.0f, 10.0f, 0.5f, 3.0f, 50.0f, 0.2f;
    c << 1.0f, -2.0f, 0.5f, 3.0f, -0.7f, 0.1f;
  }
  void gradient(nn::Tensor& x) const { x.grad = a.cwiseProduct(x.value - c); }
};

void minimise(nn::Optimizer& opt, nn::Tensor& x, const Quadratic& f, int steps) {
  for (int i = 0; i < steps; ++i) {
    f.gradient(x);
    opt.step();
  }
}

}  // namespace

TEST_CASE("Adam minimises a badly scaled quadratic", "[nn]") {
  Quadratic f;
  nn::Tensor x(3, 2);
  nn::Adam adam({nn::param_of(x, "x")}, {.lr = 0.05f});
  const float start = (x.value - f.c).norm();
  minimise(adam, x, f, 2000);
  CHECK(adam.steps_taken() == 2000);
  CHECK((x.value - f.c).cwiseAbs().maxCoeff() < 1e-3f);
  CHECK(start > 1.0f);
}

TEST_CASE("Adam's first step moves every coordinate by lr (bias correction)", "[nn]") {
  nn::Tensor x(2, 1);
  x.grad << 3.0f, -0.001f;
  nn::Adam adam({nn::param_of(x, "x")}, {.lr = 0.1f});
  adam.step();
  CHECK(x.value(0) == Approx(-0.1f).epsilon(1e-4));
  CHECK(x.value(1) == Approx(0.1f).epsilon(1e-3));
}

TEST_CASE("Adam: a moment that decays below the normal floats is flushed, in its own pass only", "[nn]") {
  // One step with a gradient, then a thousand without: beta1^1000 takes the first moment far
  // below the smallest normal float, where it must be flushed to zero, while
  // this thread's own float arithmetic keeps its subnormals afterwards.
  nn::Tensor x(20, 1);  // 16 floats on the vector path and 4 on the scalar tail
  x.value.setConstant(0.5f);
  nn::Adam adam({nn::param_of(x, "x")}, {.lr = 0.01f});
  x.grad.setConstant(1.0f);
  adam.step();
  const MatrixXf after_first = x.value;
  x.grad.setZero();
  MatrixXf at_500;
  for (int i = 1; i <= 1000; ++i) {
    adam.step();
    if (i == 500) at_500 = x.value;
  }
  // m = 0.1 * 0.9^t: normal until t ~ 820, so the weight still moves up to there, then stops.
  CHECK((at_500.array() < after_first.array()).all());
  // The saved first moment (tag, count, steps, lr, then m and v of each tensor) is exactly zero.
  std::stringstream state;
  adam.save_state(state);
  read_u32(state, "state");
  read_u32(state, "state");
  CHECK(read_u64(state, "state") == 1001);
  read_f32(state, "state");
  MatrixXf m;
  nn::read_matrix(state, m, 20, 1, "state", "m");
  CHECK(m.isZero(0.0f));
  volatile float tiny = 1e-38f;
  CHECK(tiny * 0.5f > 0.0f);  // MXCSR restored: subnormal results outside the pass
}

TEST_CASE("RMSprop minimises a quadratic in both epsilon placements", "[nn]") {
  for (bool tf_style : {false, true}) {
    Quadratic f;
    nn::Tensor x(3, 2);
    nn::RmsProp rms({nn::param_of(x, "x")}, {.lr = 0.01f, .alpha = 0.99f, .eps = 1e-5f, .tf_style = tf_style});
    minimise(rms, x, f, 3000);
    rms.set_learning_rate(0.001f);  // settle the sign-like oscillation RMSprop keeps at a fixed lr
    minimise(rms, x, f, 3000);
    INFO("tf_style " << tf_style);
    CHECK((x.value - f.c).cwiseAbs().maxCoeff() < 1e-2f);
  }
}

TEST_CASE("RMSprop first step matches the formula", "[nn]") {
  nn::Tensor x(1, 1);
  x.grad(0) = 2.0f;
  nn::RmsProp torch_like({nn::param_of(x, "x")}, {.lr = 0.1f, .alpha = 0.9f, .eps = 0.0f});
  torch_like.step();  // s = 0.1 * 4 = 0.4; x -= 0.1 * 2 / sqrt(0.4)
  CHECK(x.value(0) == Approx(-0.2f / std::sqrt(0.4f)));
  nn::Tensor y(1, 1);
  y.grad(0) = 2.0f;
  nn::RmsProp tf_like({nn::param_of(y, "y")}, {.lr = 0.1f, .alpha = 0.9f, .eps = 0.0f, .tf_style = true});
  tf_like.step();  // s = 0.9 * 1 + 0.1 * 4 = 1.3
  CHECK(y.value(0) == Approx(-0.2f / std::sqrt(1.3f)));
}

TEST_CASE("clip_grad_norm returns the pre-clip norm and scales to max_norm", "[nn]") {
  nn::Tensor a(1, 2), b(2, 1);
  a.grad << 3.0f, 0.0f;
  b.grad << 0.0f, 4.0f;  // global norm 5
  const nn::ParamList params{nn::param_of(a, "a"), nn::param_of(b, "b")};
  CHECK(nn::clip_grad_norm(params, 10.0f) == Approx(5.0f));
  CHECK(a.grad(0) == 3.0f);  // below the limit: untouched
  CHECK(nn::clip_grad_norm(params, 1.0f) == Approx(5.0f));
  CHECK(nn::global_grad_norm(params) == Approx(1.0f).epsilon(1e-5));
  CHECK(a.grad(0) / b.grad(1) == Approx(0.75f));  // direction kept
}

TEST_CASE("optimiser state round-trips so training continues identically", "[nn]") {
  Quadratic f;
  nn::Tensor x(3, 2), y(3, 2);
  nn::Adam a({nn::param_of(x, "x")}, {.lr = 0.05f});
  minimise(a, x, f, 10);
  std::stringstream state;
  a.save_state(state);
  y.value = x.value;
  nn::Adam b({nn::param_of(y, "y")}, {.lr = 0.5f});
  b.load_state(state, "ckpt.bin");
  CHECK(b.learning_rate() == 0.05f);
  minimise(a, x, f, 5);
  minimise(b, y, f, 5);
  CHECK(x.value == y.value);

  std::stringstream adam_state;
  a.save_state(adam_state);
  nn::RmsProp rms({nn::param_of(y, "y")});
  CHECK_THROWS_WITH(rms.load_state(adam_state, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("RMSprop"));
  nn::Tensor z(2, 2);
  nn::Adam wrong({nn::param_of(z, "z")});
  std::stringstream again;
  a.save_state(again);
  CHECK_THROWS_WITH(wrong.load_state(again, "ckpt.bin"), Catch::Contains("shape"));
  std::stringstream truncated(again.str().substr(0, 20));
  CHECK_THROWS_AS(b.load_state(truncated, "ckpt.bin"), Error);
}
