#include "batch_parts.hpp"

#include <algorithm>
#include <exception>
#include <vector>

#include "rdsim/nn/gemm.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rdsim::nn::batch_parts {

namespace {
constexpr double kPartMacs = 1 << 24;
constexpr Eigen::Index kMaxParts = 4;
constexpr Eigen::Index kPartFloats = 1 << 16, kVector = 16;

// Parts of an elementwise pass over `floats` floats in `units` units (floats, columns).
int elementwise_parts(Eigen::Index floats, Eigen::Index units) {
  return static_cast<int>(std::clamp<Eigen::Index>(std::min(floats / kPartFloats, units), 1, kMaxParts));
}

// The start of part p of n elements in `parts` parts, rounded down to a multiple of `vector`.
Eigen::Index first_aligned(int p, int parts, Eigen::Index n, Eigen::Index vector) {
  return p * n / parts / vector * vector;
}

}  // namespace

int count(double macs, Eigen::Index columns) {
  const auto by_work = static_cast<Eigen::Index>(macs / kPartMacs);
  return static_cast<int>(std::max<Eigen::Index>(1, std::min({by_work, kMaxParts, columns})));
}

void run(int parts, const std::function<void(int)>& fn) {
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(parts));
  auto part = [&](int p) {
    try {
      fn(p);
    } catch (...) {
      errors[static_cast<std::size_t>(p)] = std::current_exception();
    }
  };
#ifdef _OPENMP
  const int threads = omp_in_parallel() ? 1 : std::min(parts, gemm_threads());
  if (threads > 1) {
    // A team smaller than asked for (the runtime's limits) takes the parts in turn.
#pragma omp parallel num_threads(threads)
    for (int p = omp_get_thread_num(); p < parts; p += omp_get_num_threads()) part(p);
  } else {
    one_thread();
    for (int p = 0; p < parts; ++p) part(p);
  }
#else
  for (int p = 0; p < parts; ++p) part(p);
#endif
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

void for_elements(Eigen::Index n, const std::function<void(Eigen::Index, Eigen::Index)>& fn) {
  const int parts = elementwise_parts(n, n);
  if (parts == 1) return fn(0, n);
  auto start = [&](int p) { return p == parts ? n : first_aligned(p, parts, n, kVector); };
  run(parts, [&](int p) { fn(start(p), start(p + 1) - start(p)); });
}

void for_columns(Eigen::Index rows, Eigen::Index cols, const std::function<void(Eigen::Index, Eigen::Index)>& fn) {
  const int parts = elementwise_parts(rows * cols, cols);
  if (parts == 1) return fn(0, cols);
  run(parts, [&](int p) { fn(first(p, parts, cols), first(p + 1, parts, cols) - first(p, parts, cols)); });
}

void one_thread() {
#ifdef _OPENMP
  if (!omp_in_parallel() && omp_get_max_threads() != 1) omp_set_num_threads(1);
#endif
}

}  // namespace rdsim::nn::batch_parts
