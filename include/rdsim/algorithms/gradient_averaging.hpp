#pragma once
#include <vector>

#include "rdsim/nn/param.hpp"
#include "rdsim/parallel/communicator.hpp"

// The data-parallel step of gradient methods (see Algorithm::set_communicator): after backward()
// and before gradient clipping and the optimiser step, every rank replaces its gradients by their
// mean over all ranks. Clipping then sees the same global norm everywhere, and the update equals
// one computed on the ranks' minibatches together.
namespace rdsim {

// One allreduce of every gradient of `params`, packed into `buffer` (reused: no allocation after
// the first call), then divided by comm.size(). Nothing happens for a single process.
void average_gradients(Communicator& comm, const nn::ParamList& params, std::vector<float>& buffer);

// The mean over the ranks of `n` values, in place (one allreduce; nothing for a single process):
// for what an algorithm computes from its own rank's data besides gradients (TRPO's
// Fisher-vector products, surrogate and KL values).
void average_values(Communicator& comm, float* data, std::size_t n);
void average_values(Communicator& comm, double* data, std::size_t n);

}  // namespace rdsim
