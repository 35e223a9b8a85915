#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/nn.hpp"

using namespace rdsim;
using Eigen::MatrixXd;
using Eigen::MatrixXf;
using Eigen::VectorXd;
using Eigen::VectorXf;
using Eigen::VectorXi;

namespace {

MatrixXf random_matrix(int rows, int cols, Rng& rng, double scale = 1.0) {
  MatrixXf m(rows, cols);
  for (int i = 0; i < m.size(); ++i) m.data()[i] = static_cast<float>(scale * rng.normal());
  return m;
}

// Double-precision references, written directly from the definitions.
MatrixXd log_softmax(const MatrixXd& logits) {
  MatrixXd out = logits;
  for (int j = 0; j < logits.cols(); ++j) {
    const double m = logits.col(j).maxCoeff();
    out.col(j).array() -= m + std::log((logits.col(j).array() - m).exp().sum());
  }
  return out;
}

double weighted_log_prob(const MatrixXd& logits, const VectorXi& actions, const VectorXd& w) {
  const MatrixXd lp = log_softmax(logits);
  double s = 0.0;
  for (int j = 0; j < logits.cols(); ++j) s += w[j] * lp(actions[j], j);
  return s;
}

double weighted_entropy(const MatrixXd& logits, const VectorXd& w) {
  const MatrixXd lp = log_softmax(logits);
  double s = 0.0;
  for (int j = 0; j < logits.cols(); ++j) s -= w[j] * (lp.col(j).array().exp() * lp.col(j).array()).sum();
  return s;
}

double weighted_gaussian_log_prob(const MatrixXd& mean, const VectorXd& log_std, const MatrixXd& x,
                                  const VectorXd& w) {
  double s = 0.0;
  for (int j = 0; j < x.cols(); ++j)
    for (int d = 0; d < x.rows(); ++d) {
      const double sd = std::exp(log_std[d]);
      const double z = (x(d, j) - mean(d, j)) / sd;
      s += w[j] * (-0.5 * z * z - log_std[d] - 0.5 * std::log(2.0 * M_PI));
    }
  return s;
}

// Central-difference gradient of f at m (double).
MatrixXd numeric_gradient(MatrixXd m, const std::function<double(const MatrixXd&)>& f) {
  const double h = 1e-6;
  MatrixXd g(m.rows(), m.cols());
  for (int i = 0; i < m.size(); ++i) {
    const double saved = m.data()[i];
    m.data()[i] = saved + h;
    const double fp = f(m);
    m.data()[i] = saved - h;
    const double fm = f(m);
    m.data()[i] = saved;
    g.data()[i] = (fp - fm) / (2 * h);
  }
  return g;
}

void check_close(const MatrixXf& analytic, const MatrixXd& numeric) {
  const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
  CHECK((analytic.cast<double>() - numeric).cwiseAbs().maxCoeff() / scale < 1e-4);
}

}  // namespace

TEST_CASE("Categorical log_prob and entropy match the definitions", "[nn]") {
  Rng rng(1);
  const MatrixXf logits = random_matrix(4, 5, rng, 2.0);
  const nn::Categorical dist(logits);
  const MatrixXd ref = log_softmax(logits.cast<double>());
  CHECK((dist.log_probs().cast<double>() - ref).cwiseAbs().maxCoeff() < 1e-5);
  CHECK((dist.probs().colwise().sum().array() - 1.0f).abs().maxCoeff() < 1e-5f);
  const VectorXi actions = (VectorXi(5) << 0, 3, 2, 1, 3).finished();
  const VectorXf lp = dist.log_prob(actions);
  for (int j = 0; j < 5; ++j) CHECK(lp[j] == Approx(ref(actions[j], j)).epsilon(1e-5));
  const VectorXf h = dist.entropy();
  CHECK(h[0] == Approx(weighted_entropy(logits.col(0).cast<double>(), VectorXd::Ones(1))).epsilon(1e-5));
  // Uniform logits: entropy log(n).
  CHECK(nn::Categorical(MatrixXf::Zero(6, 1)).entropy()[0] == Approx(std::log(6.0f)));
  CHECK_THROWS_AS(dist.log_prob((VectorXi(5) << 0, 4, 0, 0, 0).finished()), Error);
}

TEST_CASE("Categorical is stable for huge logits", "[nn]") {
  MatrixXf logits(3, 2);
  logits << 1000.0f, -1000.0f, 0.0f, 0.0f, -1000.0f, 1000.0f;
  const nn::Categorical dist(logits);
  CHECK(dist.log_probs().allFinite());
  CHECK(dist.entropy().allFinite());
  CHECK(dist.mode() == (VectorXi(2) << 0, 2).finished());
  CHECK(dist.log_prob((VectorXi(2) << 1, 1).finished())[0] == Approx(-1000.0f));
}

TEST_CASE("Categorical gradients match finite differences", "[nn]") {
  Rng rng(2);
  const MatrixXf logits = random_matrix(5, 6, rng, 1.5);
  const VectorXi actions = (VectorXi(6) << 0, 4, 2, 2, 1, 3).finished();
  const VectorXf w = random_matrix(6, 1, rng);
  const nn::Categorical dist(logits);
  const VectorXd wd = w.cast<double>();
  check_close(dist.log_prob_grad(actions, w),
              numeric_gradient(logits.cast<double>(), [&](const MatrixXd& l) { return weighted_log_prob(l, actions, wd); }));
  check_close(dist.entropy_grad(w),
              numeric_gradient(logits.cast<double>(), [&](const MatrixXd& l) { return weighted_entropy(l, wd); }));
}

TEST_CASE("Categorical sampling frequencies match the probabilities", "[nn]") {
  const VectorXf p = (VectorXf(4) << 0.1f, 0.2f, 0.3f, 0.4f).finished();
  const int batch = 1000, rounds = 100;  // 100k draws: std of a frequency <= 0.0016
  const MatrixXf logits = p.array().log().matrix().replicate(1, batch);
  const nn::Categorical dist(logits);
  Rng rng(42);
  VectorXd counts = VectorXd::Zero(4);
  for (int r = 0; r < rounds; ++r) {
    const VectorXi a = dist.sample(rng);
    for (int j = 0; j < batch; ++j) counts[a[j]] += 1.0;
  }
  const VectorXd freq = counts / double(batch * rounds);
  for (int k = 0; k < 4; ++k) CHECK(std::abs(freq[k] - p[k]) < 0.01);  // > 6 standard deviations
  Rng a(5), b(5);
  CHECK(dist.sample(a) == dist.sample(b));
}

TEST_CASE("DiagGaussian log_prob, entropy and gradients", "[nn]") {
  Rng rng(3);
  const MatrixXf mean = random_matrix(3, 4, rng);
  const VectorXf log_std = (VectorXf(3) << -0.5f, 0.0f, 0.4f).finished();
  const MatrixXf x = random_matrix(3, 4, rng);
  const VectorXf w = random_matrix(4, 1, rng);
  const nn::DiagGaussian dist(mean, log_std);
  const MatrixXd md = mean.cast<double>(), xd = x.cast<double>();
  const VectorXd sd = log_std.cast<double>(), wd = w.cast<double>();

  const VectorXf lp = dist.log_prob(x);
  for (int j = 0; j < 4; ++j) {
    VectorXd one = VectorXd::Zero(4);
    one[j] = 1.0;
    CHECK(lp[j] == Approx(weighted_gaussian_log_prob(md, sd, xd, one)).epsilon(1e-5));
  }
  const double ref_entropy = (sd.array() + 0.5 + 0.5 * std::log(2 * M_PI)).sum();
  CHECK(dist.entropy()[2] == Approx(ref_entropy).epsilon(1e-5));

  const nn::DiagGaussian::Grad g = dist.log_prob_grad(x, w);
  check_close(g.mean, numeric_gradient(md, [&](const MatrixXd& m) { return weighted_gaussian_log_prob(m, sd, xd, wd); }));
  check_close(g.log_std, numeric_gradient(sd, [&](const MatrixXd& s) {
                return weighted_gaussian_log_prob(md, s.col(0), xd, wd);
              }));
  // Entropy does not depend on the mean; d/dlog_std of sum w_j H = sum w_j for every dim.
  check_close(dist.entropy_grad_log_std(w), numeric_gradient(sd, [&](const MatrixXd& s) {
                return wd.sum() * (s.array() + 0.5 + 0.5 * std::log(2 * M_PI)).sum();
              }));
  CHECK_THROWS_AS(nn::DiagGaussian(mean, VectorXf::Zero(2)), Error);
}

TEST_CASE("DiagGaussian samples have the right mean and spread", "[nn]") {
  const int n = 20000;
  const MatrixXf mean = (VectorXf(2) << 1.0f, -2.0f).finished().replicate(1, n);
  const VectorXf log_std = (VectorXf(2) << std::log(0.5f), std::log(2.0f)).finished();
  Rng rng(8);
  const nn::DiagGaussian dist(mean, log_std);
  const MatrixXf s = dist.sample(rng);
  const Eigen::VectorXd m = s.cast<double>().rowwise().mean();
  const Eigen::VectorXd var = (s.cast<double>().colwise() - m).array().square().rowwise().mean();
  // Standard errors: 0.0035 and 0.014 for the means; ~1.4% for the variances.
  CHECK(std::abs(m[0] - 1.0) < 0.03);
  CHECK(std::abs(m[1] + 2.0) < 0.1);
  CHECK(std::abs(var[0] / 0.25 - 1.0) < 0.1);
  CHECK(std::abs(var[1] / 4.0 - 1.0) < 0.1);
  CHECK(dist.mode() == mean);
}
