#pragma once
#include <Eigen/Core>
#include <functional>

// Threads for the learner without changing its arithmetic (oneDNN backend): a layer's large
// product or convolution is cut into parts by its work alone, never by the thread count; every
// part runs one-threaded oneDNN code, and the parts run side by side on up to gemm_threads()
// OpenMP threads (the threads oneDNN itself uses, so none spins beside another). The same
// config and seed then give the same bits on one thread or on several.
namespace rdsim::nn::batch_parts {

// How many parts `macs` multiply-adds spread over `columns` columns are cut into: one per 2^23
// multiply-adds (where a second thread pays for its start, about 1 ms), at most 8 (8 threads
// busy; a convolution's batch of 256 then has 32 samples a part, which oneDNN's kernels run as
// fast per sample as the whole batch), at most one per column.
int count(double macs, Eigen::Index columns);

// The first column of part p of `columns` columns cut into `parts` (p = parts: the end).
inline Eigen::Index first(int p, int parts, Eigen::Index columns) { return p * columns / parts; }

// Runs fn(p) for every part p in [0, parts): side by side on up to gemm_threads() threads, or in
// turn on this thread when that is 1 or this thread already runs a part. oneDNN runs its kernels
// one-threaded either way. Rethrows the first error (lowest part) once every part has ended.
void run(int parts, const std::function<void(int)>& fn);

// Makes oneDNN code called from this thread outside run() one-threaded; kernels must also be
// created so, as oneDNN sizes a kernel's work split from the thread count at creation.
void one_thread();

}  // namespace rdsim::nn::batch_parts
