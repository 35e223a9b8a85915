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

void one_thread() {
#ifdef _OPENMP
  if (!omp_in_parallel() && omp_get_max_threads() != 1) omp_set_num_threads(1);
#endif
}

}  // namespace rdsim::nn::batch_parts
