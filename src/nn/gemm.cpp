#include "rdsim/nn/gemm.hpp"

#include <atomic>
#include <cstdlib>

#include "rdsim/core/error.hpp"

#include "batch_parts.hpp"

#ifdef RDSIM_HAVE_ONEDNN
#include <oneapi/dnnl/dnnl.h>
#endif

namespace rdsim::nn {
namespace {

#ifdef RDSIM_HAVE_ONEDNN
constexpr bool kHaveOneDnn = true;
#else
constexpr bool kHaveOneDnn = false;
#endif

// RDSIM_GEMM, read once, else the build's default.
GemmBackend initial_backend() {
  const char* env = std::getenv("RDSIM_GEMM");
  if (env && *env) return gemm_backend_from_string(env, "environment variable RDSIM_GEMM");
  // Eigen by default: its products are the arithmetic every published learning result was
  // measured with, so the same seed keeps giving the same CSVs; oneDNN on request.
  return GemmBackend::Eigen;
}

std::atomic<GemmBackend>& backend_flag() {
  static std::atomic<GemmBackend> flag{initial_backend()};
  return flag;
}

std::atomic<int>& thread_count() {
  static std::atomic<int> count{1};
  return count;
}

void eigen_matmul(const Eigen::Ref<const Eigen::MatrixXf>& a, Op op_a, const Eigen::Ref<const Eigen::MatrixXf>& b,
                  Op op_b, Eigen::Ref<Eigen::MatrixXf> c, bool accumulate) {
  // The expressions the networks always used, so that the Eigen backend keeps their arithmetic.
  const bool ta = op_a == Op::Transpose, tb = op_b == Op::Transpose;
  if (accumulate) {
    if (!ta && !tb) c.noalias() += a * b;
    else if (!ta) c.noalias() += a * b.transpose();
    else if (!tb) c.noalias() += a.transpose() * b;
    else c.noalias() += a.transpose() * b.transpose();
  } else {
    if (!ta && !tb) c.noalias() = a * b;
    else if (!ta) c.noalias() = a * b.transpose();
    else if (!tb) c.noalias() = a.transpose() * b;
    else c.noalias() = a.transpose() * b.transpose();
  }
}

#ifdef RDSIM_HAVE_ONEDNN
// One-threaded sgemm (batch_parts::run makes oneDNN one-threaded).
void onednn_sgemm(const Eigen::Ref<const Eigen::MatrixXf>& a, Op op_a, const Eigen::Ref<const Eigen::MatrixXf>& b,
                  Op op_b, Eigen::Ref<Eigen::MatrixXf> c, bool accumulate, Eigen::Index k) {
  // dnnl_sgemm is row-major; a column-major C (m x n) is the row-major C^T, and
  // C^T = op(B)^T op(A)^T: the same call with the operands swapped and their flags kept.
  const auto m = static_cast<dnnl_dim_t>(c.rows()), n = static_cast<dnnl_dim_t>(c.cols());
  const dnnl_status_t status =
      dnnl_sgemm(op_b == Op::Transpose ? 'T' : 'N', op_a == Op::Transpose ? 'T' : 'N', n, m,
                 static_cast<dnnl_dim_t>(k), 1.0f, b.data(), static_cast<dnnl_dim_t>(b.outerStride()), a.data(),
                 static_cast<dnnl_dim_t>(a.outerStride()), accumulate ? 1.0f : 0.0f, c.data(),
                 static_cast<dnnl_dim_t>(c.outerStride()));
  if (status != dnnl_success) throw Error("nn::matmul: oneDNN's sgemm failed (status " + std::to_string(status) + ")");
}

// C's columns cut into parts (batch_parts: by the work, so the same bits on any thread count),
// each part's columns op(A) op(B)[:, part] by a one-threaded sgemm.
void onednn_matmul(const Eigen::Ref<const Eigen::MatrixXf>& a, Op op_a, const Eigen::Ref<const Eigen::MatrixXf>& b,
                   Op op_b, Eigen::Ref<Eigen::MatrixXf> c, bool accumulate, Eigen::Index k) {
  const Eigen::Index n = c.cols();
  const int parts = batch_parts::count(static_cast<double>(c.rows()) * static_cast<double>(n) * static_cast<double>(k), n);
  batch_parts::run(parts, [&](int p) {
    const Eigen::Index first = batch_parts::first(p, parts, n), cols = batch_parts::first(p + 1, parts, n) - first;
    // Columns [first, first + cols) of op(B): columns of B, or rows of B when transposed.
    if (op_b == Op::Transpose) onednn_sgemm(a, op_a, b.middleRows(first, cols), op_b, c.middleCols(first, cols), accumulate, k);
    else onednn_sgemm(a, op_a, b.middleCols(first, cols), op_b, c.middleCols(first, cols), accumulate, k);
  });
}
#endif

}  // namespace

bool onednn_available() { return kHaveOneDnn; }

GemmBackend gemm_backend() { return backend_flag().load(std::memory_order_relaxed); }

void set_gemm_backend(GemmBackend backend) {
  if (backend == GemmBackend::OneDnn && !kHaveOneDnn)
    throw Error("nn: this rdsim was built without oneDNN (CMake RDSIM_ONEDNN; Debian libdnnl-dev): only the eigen GEMM");
  backend_flag().store(backend, std::memory_order_relaxed);
}

GemmBackend gemm_backend_from_string(const std::string& name, const std::string& where) {
  if (name == "eigen") return GemmBackend::Eigen;
  if (name == "onednn") {
    if (!kHaveOneDnn)
      throw Error(where + ": \"onednn\": this rdsim was built without oneDNN (Debian libdnnl-dev, then rebuild); expected \"eigen\"");
    return GemmBackend::OneDnn;
  }
  throw Error(where + ": expected one of \"eigen\", \"onednn\", got \"" + name + "\"");
}

const char* to_string(GemmBackend backend) { return backend == GemmBackend::OneDnn ? "onednn" : "eigen"; }

void set_gemm_threads(int threads) {
  if (threads < 1) throw Error("nn: GEMM threads must be at least 1, got " + std::to_string(threads));
  thread_count().store(threads, std::memory_order_relaxed);
}

int gemm_threads() { return thread_count().load(std::memory_order_relaxed); }

void run_side_by_side(int count, const std::function<void(int)>& task) { batch_parts::run(count, task); }

GemmScope::GemmScope(GemmBackend backend, int threads) : saved_backend_(gemm_backend()), saved_threads_(gemm_threads()) {
  set_gemm_backend(backend);
  set_gemm_threads(threads);
}

GemmScope::~GemmScope() {
  set_gemm_backend(saved_backend_);
  set_gemm_threads(saved_threads_);
}

void matmul(const Eigen::Ref<const Eigen::MatrixXf>& a, Op op_a, const Eigen::Ref<const Eigen::MatrixXf>& b, Op op_b,
            Eigen::Ref<Eigen::MatrixXf> c, bool accumulate) {
  const Eigen::Index a_rows = op_a == Op::Transpose ? a.cols() : a.rows();
  const Eigen::Index k = op_a == Op::Transpose ? a.rows() : a.cols();
  const Eigen::Index b_rows = op_b == Op::Transpose ? b.cols() : b.rows();
  const Eigen::Index b_cols = op_b == Op::Transpose ? b.rows() : b.cols();
  if (k != b_rows || c.rows() != a_rows || c.cols() != b_cols)
    throw Error("nn::matmul: shapes " + std::to_string(a_rows) + "x" + std::to_string(k) + " * " +
                std::to_string(b_rows) + "x" + std::to_string(b_cols) + " -> " + std::to_string(c.rows()) + "x" +
                std::to_string(c.cols()) + " do not match");
#ifdef RDSIM_HAVE_ONEDNN
  if (gemm_backend() == GemmBackend::OneDnn) {
    if (c.size() == 0) return;
    if (k == 0) {
      if (!accumulate) c.setZero();
      return;
    }
    onednn_matmul(a, op_a, b, op_b, c, accumulate, k);
    return;
  }
#endif
  eigen_matmul(a, op_a, b, op_b, c, accumulate);
}

}  // namespace rdsim::nn
