#include <catch2/catch.hpp>

#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/nn.hpp"

using namespace rdsim;
using Eigen::MatrixXd;
using Eigen::MatrixXf;

namespace {

MatrixXf random_matrix(Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  MatrixXf m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<float>(rng.normal());
  return m;
}

// Restores the GEMM backend and thread count a test changed.
struct BackendScope {
  nn::GemmBackend backend = nn::gemm_backend();
  int threads = nn::gemm_threads();
  ~BackendScope() {
    nn::set_gemm_backend(backend);
    nn::set_gemm_threads(threads);
  }
};

std::vector<nn::GemmBackend> backends() {
  std::vector<nn::GemmBackend> list = {nn::GemmBackend::Eigen};
  if (nn::onednn_available()) list.push_back(nn::GemmBackend::OneDnn);
  return list;
}

MatrixXd op(const MatrixXf& m, nn::Op o) {
  return o == nn::Op::Transpose ? MatrixXd(m.cast<double>().transpose()) : MatrixXd(m.cast<double>());
}

// Max |a - b| relative to the largest |b|.
double relative_difference(const MatrixXd& a, const MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

}  // namespace

TEST_CASE("matmul computes op(A) op(B), overwriting or accumulating, on every backend and thread count", "[nn]") {
  BackendScope scope;
  Rng rng(3);
  const int m = 37, k = 53, n = 29;  // odd sizes: the kernels' edge cases
  for (const nn::GemmBackend backend : backends()) {
    nn::set_gemm_backend(backend);
    for (const int threads : {1, 2}) {
      if (backend == nn::GemmBackend::Eigen && threads > 1) continue;
      nn::set_gemm_threads(threads);
      for (const nn::Op oa : {nn::Op::None, nn::Op::Transpose})
        for (const nn::Op ob : {nn::Op::None, nn::Op::Transpose}) {
          const MatrixXf a = oa == nn::Op::None ? random_matrix(m, k, rng) : random_matrix(k, m, rng);
          const MatrixXf b = ob == nn::Op::None ? random_matrix(k, n, rng) : random_matrix(n, k, rng);
          const MatrixXf c0 = random_matrix(m, n, rng);
          const MatrixXd product = op(a, oa) * op(b, ob);
          INFO(nn::to_string(backend) << " threads " << threads << " transposes " << (oa == nn::Op::Transpose)
                                      << (ob == nn::Op::Transpose));
          MatrixXf c = c0;
          nn::matmul(a, oa, b, ob, c);
          CHECK(relative_difference(c.cast<double>(), product) < 1e-5);
          c = c0;
          nn::matmul(a, oa, b, ob, c, true);
          CHECK(relative_difference(c.cast<double>(), product + c0.cast<double>()) < 1e-5);
        }
    }
  }
}

TEST_CASE("oneDNN's products of a large batch give the same bits on 1, 2 and 3 threads", "[nn]") {
  if (!nn::onednn_available()) return;  // this build has only the eigen backend
  BackendScope scope;
  nn::set_gemm_backend(nn::GemmBackend::OneDnn);
  Rng rng(5);
  const int m = 300, k = 257, n = 701;  // 54M multiply-adds: cut into 3 parts of uneven sizes
  for (const nn::Op oa : {nn::Op::None, nn::Op::Transpose})
    for (const nn::Op ob : {nn::Op::None, nn::Op::Transpose}) {
      INFO("transposes " << (oa == nn::Op::Transpose) << (ob == nn::Op::Transpose));
      const MatrixXf a = oa == nn::Op::None ? random_matrix(m, k, rng) : random_matrix(k, m, rng);
      const MatrixXf b = ob == nn::Op::None ? random_matrix(k, n, rng) : random_matrix(n, k, rng);
      const MatrixXf c0 = random_matrix(m, n, rng);
      std::vector<MatrixXf> results;
      for (const int threads : {1, 2, 3}) {
        nn::set_gemm_threads(threads);
        MatrixXf c = c0;
        nn::matmul(a, oa, b, ob, c, true);
        results.push_back(c);
      }
      CHECK(relative_difference(results[0].cast<double>(), op(a, oa) * op(b, ob) + c0.cast<double>()) < 1e-5);
      CHECK(results[1] == results[0]);
      CHECK(results[2] == results[0]);
    }
}

TEST_CASE("matmul works on column blocks of bigger matrices and on empty products", "[nn]") {
  BackendScope scope;
  Rng rng(4);
  for (const nn::GemmBackend backend : backends()) {
    nn::set_gemm_backend(backend);
    INFO(nn::to_string(backend));
    // Columns 3..9 of a 20 x 12 matrix, written into rows 0..4 of a 9 x 7 one (outer stride 9).
    const MatrixXf a = random_matrix(5, 20, rng), big = random_matrix(20, 12, rng);
    MatrixXf out = MatrixXf::Constant(9, 7, 7.0f);
    nn::matmul(a, nn::Op::None, big.middleCols(3, 7), nn::Op::None, out.topRows(5));
    CHECK(relative_difference(out.topRows(5).cast<double>(), a.cast<double>() * big.middleCols(3, 7).cast<double>()) < 1e-5);
    CHECK((out.bottomRows(4).array() == 7.0f).all());  // rows outside the block untouched
    // k = 0: the product is zero.
    MatrixXf c = MatrixXf::Constant(3, 4, 1.0f);
    nn::matmul(MatrixXf(3, 0), nn::Op::None, MatrixXf(0, 4), nn::Op::None, c, true);
    CHECK((c.array() == 1.0f).all());
    nn::matmul(MatrixXf(3, 0), nn::Op::None, MatrixXf(0, 4), nn::Op::None, c);
    CHECK(c.isZero(0.0f));
    MatrixXf none(0, 4);
    nn::matmul(MatrixXf(0, 2), nn::Op::None, MatrixXf(2, 4), nn::Op::None, none);
  }
  MatrixXf wrong(2, 2);
  CHECK_THROWS_AS(nn::matmul(MatrixXf(2, 3), nn::Op::None, MatrixXf(2, 2), nn::Op::None, wrong), Error);
}

TEST_CASE("The eigen backend keeps Eigen's own products bit for bit", "[nn]") {
  BackendScope scope;
  nn::set_gemm_backend(nn::GemmBackend::Eigen);
  Rng rng(5);
  const MatrixXf w = random_matrix(64, 23, rng), x = random_matrix(23, 512, rng), g = random_matrix(64, 512, rng);
  MatrixXf y(64, 512), dx(23, 512), dw = random_matrix(64, 23, rng);
  const MatrixXf dw0 = dw;
  nn::matmul(w, nn::Op::None, x, nn::Op::None, y);
  nn::matmul(w, nn::Op::Transpose, g, nn::Op::None, dx);
  nn::matmul(g, nn::Op::None, x, nn::Op::Transpose, dw, true);
  MatrixXf y_ref(64, 512), dx_ref(23, 512), dw_ref = dw0;
  y_ref.noalias() = w * x;
  dx_ref.noalias() = w.transpose() * g;
  dw_ref.noalias() += g * x.transpose();
  CHECK(y == y_ref);
  CHECK(dx == dx_ref);
  CHECK(dw == dw_ref);
}

TEST_CASE("bias_activate equals adding the bias and then activating, bit for bit", "[nn]") {
  Rng rng(6);
  const MatrixXf z = random_matrix(19, 33, rng);
  const Eigen::VectorXf b = random_matrix(19, 1, rng);
  for (const nn::Activation a : {nn::Activation::Tanh, nn::Activation::ReLU, nn::Activation::Identity}) {
    MatrixXf fused = z, separate = z;
    nn::bias_activate(fused, b, a);
    separate.colwise() += b;
    nn::activate(separate, a);
    INFO(nn::to_string(a));
    CHECK(fused == separate);
  }
}

TEST_CASE("An Mlp and a Cnn give the same outputs and gradients on the eigen and onednn backends", "[nn]") {
  if (!nn::onednn_available()) return;  // this build has only the eigen backend
  BackendScope scope;
  Rng rng(7);
  nn::Mlp mlp({11, {64, 64}, 6, nn::Activation::Tanh}, 1.0f, rng);
  nn::Cnn cnn(nn::small_cnn({36, 36, 3}, 5), 1.0f, rng);
  for (nn::Network* net : std::vector<nn::Network*>{&mlp, &cnn}) {
    const MatrixXf x = random_matrix(net->input_size(), 17, rng).cwiseAbs();
    const MatrixXf c = random_matrix(net->output_size(), 17, rng);
    std::vector<MatrixXf> outputs, input_grads, param_grads;
    for (const nn::GemmBackend backend : backends()) {
      nn::set_gemm_backend(backend);
      net->zero_grad();
      outputs.push_back(net->forward(x));
      input_grads.push_back(net->backward(c));
      param_grads.push_back(nn::flatten_grads(net->params()));
    }
    CHECK(relative_difference(outputs[1].cast<double>(), outputs[0].cast<double>()) < 1e-5);
    CHECK(relative_difference(input_grads[1].cast<double>(), input_grads[0].cast<double>()) < 1e-5);
    CHECK(relative_difference(param_grads[1].cast<double>(), param_grads[0].cast<double>()) < 1e-5);
  }
}

TEST_CASE("oneDNN's convolution equals Eigen's, bit for bit on 1, 2 and 3 threads, padded or not", "[nn][conv]") {
  if (!nn::onednn_available()) return;  // this build has only the eigen backend
  BackendScope scope;
  Rng rng(9);
  // 30 x 30 with 4 x 4 kernels at stride 3: the last rows and columns feed no output pixel, so
  // their input gradient must come back zero. Batch 513: cut into parts of uneven sizes.
  for (int padding : {0, 1}) {
    INFO("padding " << padding);
    nn::Conv2d conv({30, 30, 3}, {32, 4, 3, padding}, 1.0f, rng);
    conv.bias.value = random_matrix(32, 1, rng);
    const Eigen::Index batch = 513;
    REQUIRE(double(conv.spec.out_channels) * conv.patch_size() * conv.output.height * conv.output.width * batch >=
            3 * (1 << 24));  // three parts (batch_parts.hpp)
    const MatrixXf x = random_matrix(conv.in_size(), batch, rng);
    const MatrixXf c = random_matrix(conv.out_size(), batch, rng);
    struct Result {
      MatrixXf y, gx, gw, gb;
    };
    auto run = [&](nn::GemmBackend backend, int threads) {
      nn::set_gemm_backend(backend);
      nn::set_gemm_threads(threads);
      nn::ConvWorkspace ws;
      Result r;
      conv.forward(x, r.y, ws);
      conv.weight.zero_grad();
      conv.bias.zero_grad();
      r.gx.setConstant(conv.in_size(), batch, 7.0f);  // overwritten, not added to
      conv.backward(x, c, &r.gx, ws);
      conv.backward(x, c, nullptr, ws);  // accumulates: twice the gradient
      r.gw = conv.weight.grad / 2;
      r.gb = conv.bias.grad / 2;
      return r;
    };
    const Result eigen = run(nn::GemmBackend::Eigen, 1);
    const Result one = run(nn::GemmBackend::OneDnn, 1);
    CHECK(relative_difference(one.y.cast<double>(), eigen.y.cast<double>()) < 1e-5);
    CHECK(relative_difference(one.gx.cast<double>(), eigen.gx.cast<double>()) < 1e-5);
    CHECK(relative_difference(one.gw.cast<double>(), eigen.gw.cast<double>()) < 1e-5);
    CHECK(relative_difference(one.gb.cast<double>(), eigen.gb.cast<double>()) < 1e-5);
    for (int threads : {2, 3}) {
      INFO(threads << " threads");
      const Result many = run(nn::GemmBackend::OneDnn, threads);
      CHECK(many.y == one.y);
      CHECK(many.gx == one.gx);
      CHECK(many.gw == one.gw);
      CHECK(many.gb == one.gb);
    }
  }
}

TEST_CASE("GEMM backend names and thread counts are checked", "[nn]") {
  CHECK(nn::gemm_backend_from_string("eigen", "x") == nn::GemmBackend::Eigen);
  CHECK_THROWS_WITH(nn::gemm_backend_from_string("mkl", "cfg: gemm"), Catch::Contains("cfg: gemm: expected one of"));
  CHECK_THROWS_AS(nn::set_gemm_threads(0), Error);
  if (nn::onednn_available())
    CHECK(nn::gemm_backend_from_string("onednn", "x") == nn::GemmBackend::OneDnn);
  else
    CHECK_THROWS_AS(nn::set_gemm_backend(nn::GemmBackend::OneDnn), Error);
}
