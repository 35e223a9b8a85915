#include "rdsim/algorithms/gradient_averaging.hpp"

#include <algorithm>

namespace rdsim {

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
  comm.allreduce_sum(buffer.data(), total);
  const float inv = 1.0f / static_cast<float>(comm.size());
  at = 0;
  for (const nn::Param& p : params) {
    float* g = p.grad->data();
    for (Eigen::Index k = 0; k < p.grad->size(); ++k) g[k] = buffer[at + static_cast<std::size_t>(k)] * inv;
    at += static_cast<std::size_t>(p.grad->size());
  }
}

}  // namespace rdsim
