#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>

// The one matrix product of the networks (dense layers, convolutions): C = op(A) op(B) or
// C += op(A) op(B), float32, column-major. Two backends compute it:
//   Eigen:  Eigen's own GEMM, the arithmetic rdsim always had.
//   oneDNN: dnnl_sgemm of oneDNN (Debian libdnnl-dev), JIT kernels for the CPU it runs on; about
//           1.3-3x Eigen's speed on the networks' shapes, and it can use several threads (with
//           the same results on any count). Its summation order differs from Eigen's, so results
//           differ in the last bits (and so do training CSVs against an Eigen build; the same
//           build, backend and seed still give the same CSV).
// The default is Eigen (the arithmetic of every published learning result); oneDNN where the build
// has it (CMake RDSIM_ONEDNN) on request: the environment variable RDSIM_GEMM=eigen|onednn chooses
// at start, set_gemm_backend() at run time.
namespace rdsim::nn {

enum class GemmBackend { Eigen, OneDnn };

// True when this build links oneDNN.
bool onednn_available();
GemmBackend gemm_backend();
// rdsim::Error when asking for oneDNN in a build without it.
void set_gemm_backend(GemmBackend backend);
// "eigen" | "onednn" -> GemmBackend; rdsim::Error naming `where` otherwise (or oneDNN not built in).
GemmBackend gemm_backend_from_string(const std::string& name, const std::string& where);
const char* to_string(GemmBackend backend);

// Threads of the learner (OpenMP; 1 by default): the oneDNN backend's products and convolutions,
// and on either backend the large elementwise passes (activations, Adam's step). A large one is cut
// into parts by its work alone, and the parts run side by side on up to this many threads, so
// results are the same bits on any thread count (src/nn/batch_parts.hpp). Eigen's products always
// run on the calling thread.
void set_gemm_threads(int threads);
int gemm_threads();

// Runs task(i) for every i in [0, count) side by side on up to gemm_threads() threads (in turn on
// one), for independent work such as SAC's two critics, whose layers are each too small to be cut
// into parts. The products inside a task run one-threaded, cut as they always are, so a task
// that touches only its own networks and outputs gives the same bits on any thread count.
// Rethrows the first error (lowest i) once every task has ended.
void run_side_by_side(int count, const std::function<void(int)>& task);

// Sets the backend and thread count for its lifetime, then restores the ones before.
class GemmScope {
public:
  GemmScope(GemmBackend backend, int threads);
  ~GemmScope();
  GemmScope(const GemmScope&) = delete;
  GemmScope& operator=(const GemmScope&) = delete;

private:
  GemmBackend saved_backend_;
  int saved_threads_;
};

enum class Op { None, Transpose };

// c = op(a) op(b) (accumulate false; c must already have its shape) or c += op(a) op(b).
void matmul(const Eigen::Ref<const Eigen::MatrixXf>& a, Op op_a, const Eigen::Ref<const Eigen::MatrixXf>& b, Op op_b,
            Eigen::Ref<Eigen::MatrixXf> c, bool accumulate = false);

}  // namespace rdsim::nn
