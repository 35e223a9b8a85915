#pragma once
#include <Eigen/Core>
#include <functional>

// Threads for the learner without changing its arithmetic (oneDNN backend): a layer's large
// product or convolution is cut into parts by its work alone, never by the thread count; every
// part runs one-threaded oneDNN code, and the parts run side by side on up to gemm_threads()
// OpenMP threads (the threads oneDNN itself uses, so none spins beside another). The same
// config and seed then give the same bits on one thread or on several.
namespace rdsim::nn::batch_parts {

// How many parts `macs` multiply-adds spread over `columns` columns are cut into: one per 2^24
// multiply-adds, at most 4, at most one per column. Each part packs its operands anew, so fewer,
// larger parts are faster on few threads, and more parts use more threads. Measured with `rdsim
// bench-learner` on 2 cores (AMD EPYC, AVX-512), ms per update on 1 | 2 threads, two interleaved
// rounds: 2^24 and 4 parts: ppo_mlp_512 17.4, 17.0 | 9.6, 9.5, ppo_cnn_small_64 18.9, 18.2 | 9.8,
// 9.7; 2^23 and 8 parts: 17.9, 17.8 | 10.5, 9.8 and 19.1, 19.0 | 9.9, 9.8.
int count(double macs, Eigen::Index columns);

// The first column of part p of `columns` columns cut into `parts` (p = parts: the end).
inline Eigen::Index first(int p, int parts, Eigen::Index columns) { return p * columns / parts; }

// Runs fn(p) for every part p in [0, parts): side by side on up to gemm_threads() threads, or in
// turn on this thread when that is 1 or this thread already runs a part. oneDNN runs its kernels
// one-threaded either way. Rethrows the first error (lowest part) once every part has ended.
void run(int parts, const std::function<void(int)>& fn);

// An elementwise pass over n floats (an activation, an optimiser step) cut into parts: one per
// 2^16 floats (about 30 us of a memory-bound pass), at most 4, and runs fn(first, size) for each
// as run() does. Every part but the last is a multiple of 16 floats long and starts at one, so
// each float takes the same vector or scalar path as in one pass over all of them: the same bits.
void for_elements(Eigen::Index n, const std::function<void(Eigen::Index, Eigen::Index)>& fn);

// The same for a pass over a rows x cols matrix column by column: parts of whole columns.
void for_columns(Eigen::Index rows, Eigen::Index cols, const std::function<void(Eigen::Index, Eigen::Index)>& fn);

// Makes oneDNN code called from this thread outside run() one-threaded; kernels must also be
// created so, as oneDNN sizes a kernel's work split from the thread count at creation.
void one_thread();

}  // namespace rdsim::nn::batch_parts
