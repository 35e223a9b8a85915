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

namespace {

// KL(p || q) of two categoricals given by logits, and of two diagonal Gaussians, in double.
double categorical_kl(const MatrixXd& p_logits, const MatrixXd& q_logits) {
  const MatrixXd lp = log_softmax(p_logits), lq = log_softmax(q_logits);
  return (lp.array().exp() * (lp - lq).array()).sum();
}

double gaussian_kl(const MatrixXd& mp, const VectorXd& sp, const MatrixXd& mq, const VectorXd& sq) {
  double kl = 0.0;
  for (int j = 0; j < mp.cols(); ++j)
    for (int d = 0; d < mp.rows(); ++d) {
      const double vp = std::exp(2 * sp[d]), vq = std::exp(2 * sq[d]);
      kl += sq[d] - sp[d] + (vp + std::pow(mp(d, j) - mq(d, j), 2)) / (2 * vq) - 0.5;
    }
  return kl;
}

// Second derivative of f along (u, v) at m: (f(m + e(u+v)) - f(m + e(u-v)) - f(m - e(u-v)) + f(m - e(u+v))) / (4 e^2).
double mixed_second_derivative(const MatrixXd& m, const MatrixXd& u, const MatrixXd& v,
                               const std::function<double(const MatrixXd&)>& f) {
  const double e = 1e-4;
  return (f(m + e * (u + v)) - f(m + e * (u - v)) - f(m - e * (u - v)) + f(m - e * (u + v))) / (4 * e * e);
}

}  // namespace

TEST_CASE("KL divergences match their definitions", "[nn]") {
  Rng rng(11);
  const MatrixXf a = random_matrix(4, 3, rng, 1.5), b = random_matrix(4, 3, rng, 1.5);
  const VectorXf kl = nn::Categorical(a).kl_divergence(nn::Categorical(b));
  CHECK(kl.sum() == Approx(categorical_kl(a.cast<double>(), b.cast<double>())).epsilon(1e-4));
  CHECK(kl[1] == Approx(categorical_kl(a.col(1).cast<double>(), b.col(1).cast<double>())).epsilon(1e-4));
  CHECK(nn::Categorical(a).kl_divergence(nn::Categorical(a)).cwiseAbs().maxCoeff() < 1e-6f);

  const MatrixXf ma = random_matrix(2, 5, rng), mb = random_matrix(2, 5, rng);
  const VectorXf sa = (VectorXf(2) << -0.3f, 0.2f).finished(), sb = (VectorXf(2) << 0.1f, -0.5f).finished();
  const VectorXf gkl = nn::DiagGaussian(ma, sa).kl_divergence(nn::DiagGaussian(mb, sb));
  CHECK(gkl.sum() == Approx(gaussian_kl(ma.cast<double>(), sa.cast<double>(), mb.cast<double>(), sb.cast<double>())).epsilon(1e-4));
  CHECK(gkl.minCoeff() >= 0.0f);
}

TEST_CASE("Fisher products are the Hessians of the KL divergence at equality", "[nn]") {
  Rng rng(12);
  // Categorical: d^2/dq^2 KL(p || q) at q = p, along (u, v), against (diag p - p p^T) v.
  const MatrixXf logits = random_matrix(4, 3, rng);
  const MatrixXf u = random_matrix(4, 3, rng), v = random_matrix(4, 3, rng);
  const nn::Categorical dist(logits);
  const double analytic = u.cwiseProduct(dist.fisher_product(v)).cast<double>().sum();
  const MatrixXd ld = logits.cast<double>();
  const double numeric = mixed_second_derivative(ld, u.cast<double>(), v.cast<double>(),
                                                 [&](const MatrixXd& q) { return categorical_kl(ld, q); });
  CHECK(analytic == Approx(numeric).epsilon(1e-3));

  // Gaussian means: d^2/dmean_q^2 KL = 1 / sigma^2.
  const MatrixXf mean = random_matrix(2, 3, rng), um = random_matrix(2, 3, rng), vm = random_matrix(2, 3, rng);
  const VectorXf log_std = (VectorXf(2) << -0.4f, 0.3f).finished();
  const nn::DiagGaussian g(mean, log_std);
  const double ga = um.cwiseProduct(g.fisher_product_mean(vm)).cast<double>().sum();
  const MatrixXd md = mean.cast<double>();
  const VectorXd sd = log_std.cast<double>();
  const double gn = mixed_second_derivative(md, um.cast<double>(), vm.cast<double>(),
                                            [&](const MatrixXd& q) { return gaussian_kl(md, sd, q, sd); });
  CHECK(ga == Approx(gn).epsilon(1e-3));
  // Log std: d^2/dlog_std_q^2 KL = 2 per sample and dim at equality.
  const double e = 1e-4;
  const auto kl_ls = [&](double delta) {
    VectorXd s = sd;
    s[0] += delta;
    return gaussian_kl(md, sd, md, s);
  };
  CHECK((kl_ls(e) - 2 * kl_ls(0) + kl_ls(-e)) / (e * e) == Approx(2.0 * 3).epsilon(1e-3));
}

namespace {

// Reference TanhGaussian in double: actions and sum_j [sum_d ga a + gl log pi].
struct TanhRef {
  MatrixXd noise;
  MatrixXd actions(const MatrixXd& mean, const MatrixXd& log_std) const {
    return (mean.array() + log_std.array().exp() * noise.array()).tanh().matrix();
  }
  VectorXd log_probs(const MatrixXd& mean, const MatrixXd& log_std) const {
    const MatrixXd u = mean.array() + log_std.array().exp() * noise.array();
    VectorXd out(mean.cols());
    for (int j = 0; j < mean.cols(); ++j) {
      double lp = 0.0;
      for (int d = 0; d < mean.rows(); ++d)
        lp += -0.5 * noise(d, j) * noise(d, j) - log_std(d, j) - 0.5 * std::log(2 * M_PI) -
              std::log(1.0 - std::pow(std::tanh(u(d, j)), 2));
      out[j] = lp;
    }
    return out;
  }
  double objective(const MatrixXd& mean, const MatrixXd& log_std, const MatrixXd& ga, const VectorXd& gl) const {
    return actions(mean, log_std).cwiseProduct(ga).sum() + log_probs(mean, log_std).dot(gl);
  }
};

}  // namespace

TEST_CASE("TanhGaussian: squashed actions, change-of-variables log-density, reparameterised gradients", "[nn]") {
  Rng rng(13);
  const MatrixXf mean = random_matrix(2, 5, rng), log_std = random_matrix(2, 5, rng, 0.5), noise = random_matrix(2, 5, rng);
  const nn::TanhGaussian dist(mean, log_std, noise);
  const TanhRef ref{noise.cast<double>()};
  const MatrixXd md = mean.cast<double>(), sd = log_std.cast<double>();
  CHECK((dist.actions().cast<double>() - ref.actions(md, sd)).cwiseAbs().maxCoeff() < 1e-6);
  CHECK((dist.log_probs().cast<double>() - ref.log_probs(md, sd)).cwiseAbs().maxCoeff() < 1e-4);
  CHECK(dist.actions().cwiseAbs().maxCoeff() < 1.0f);
  CHECK(nn::TanhGaussian::mode(mean) == MatrixXf(mean.array().tanh()));

  const MatrixXf ga = random_matrix(2, 5, rng);
  const VectorXf gl = random_matrix(5, 1, rng);
  const nn::TanhGaussian::Grad g = dist.backward(ga, gl);
  const MatrixXd gad = ga.cast<double>();
  const VectorXd gld = gl.cast<double>();
  check_close(g.mean, numeric_gradient(md, [&](const MatrixXd& m) { return ref.objective(m, sd, gad, gld); }));
  check_close(g.log_std, numeric_gradient(sd, [&](const MatrixXd& s) { return ref.objective(md, s, gad, gld); }));

  // Far in the tails the stable form keeps the log-density finite (1 - tanh^2 underflows in float).
  const nn::TanhGaussian tail(MatrixXf::Constant(1, 1, 30.0f), MatrixXf::Zero(1, 1), MatrixXf::Zero(1, 1));
  CHECK(std::isfinite(tail.log_probs()[0]));
  CHECK(tail.log_probs()[0] == Approx(-0.5 * std::log(2 * M_PI) - 2.0 * (std::log(2.0) - 30.0 - std::log1p(std::exp(-60.0)))));
}
