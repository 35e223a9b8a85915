#include "rdsim/algorithms/gradient_averaging.hpp"

#include <algorithm>

namespace rdsim {

namespace {

template <class T>
void average(Communicator& comm, T* data, std::size_t n) {
  if (comm.size() == 1) return;
  comm.allreduce_sum(data, n);
  const T inv = T(1) / static_cast<T>(comm.size());
  for (std::size_t k = 0; k < n; ++k) data[k] *= inv;
}

}  // namespace

void average_values(Communicator& comm, float* data, std::size_t n) { average(comm, data, n); }
void average_values(Communicator& comm, double* data, std::size_t n) { average(comm, data, n); }

void average_gradients(Communicator& comm, const nn::ParamList& params, std::vector<float>& buffer) {
  if (comm.size() == 1) return;
  std::size_t total = 0;
  for (const nn::Param& p : params) total += static_cast<std::size_t>(p.grad->size());
  buffer.resize(total);
  std::size_t at = 0;
  for (const nn::Param& p : params) {
    std::copy_n(p.grad->data(), p.grad->size(), buffer.data() + at);
    at += static_cast<std::size_t>(p.grad->size());
  }
  average_values(comm, buffer.data(), total);
  at = 0;
  for (const nn::Param& p : params) {
    std::copy_n(buffer.data() + at, p.grad->size(), p.grad->data());
    at += static_cast<std::size_t>(p.grad->size());
  }
}

}  // namespace rdsim
