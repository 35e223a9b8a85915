#include "rdsim/nn/network.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim::nn {
namespace {

// Parameter views of `other`: params() hands out mutable views; copying and blending only read them.
ParamList source_params(const Network& other) { return const_cast<Network&>(other).params(); }

void check_same_params(const ParamList& mine, const ParamList& theirs) {
  bool same = mine.size() == theirs.size();
  for (size_t i = 0; same && i < mine.size(); ++i)
    same = mine[i].name == theirs[i].name && mine[i].value->rows() == theirs[i].value->rows() &&
           mine[i].value->cols() == theirs[i].value->cols();
  if (!same) throw Error("nn: cannot copy values between networks of different shapes");
}

}  // namespace

void Network::zero_grad() { nn::zero_grad(params()); }

void Network::copy_values_from(const Network& other) {
  const ParamList mine = params(), theirs = source_params(other);
  check_same_params(mine, theirs);
  for (size_t i = 0; i < mine.size(); ++i) *mine[i].value = *theirs[i].value;
}

void Network::blend_values_from(const Network& other, float tau) {
  const ParamList mine = params(), theirs = source_params(other);
  check_same_params(mine, theirs);
  for (size_t i = 0; i < mine.size(); ++i) *mine[i].value = tau * *theirs[i].value + (1.0f - tau) * *mine[i].value;
}

}  // namespace rdsim::nn
