#include "rdsim/nn/init.hpp"

#include <Eigen/QR>

namespace rdsim::nn {

void orthogonal_init(Eigen::MatrixXf& weights, float gain, Rng& rng) {
  const Eigen::Index rows = weights.rows(), cols = weights.cols();
  if (rows == 0 || cols == 0) return;
  // QR needs a tall matrix; a wide one is the transpose of a tall one.
  const Eigen::Index tall = std::max(rows, cols), thin = std::min(rows, cols);
  Eigen::MatrixXd gaussian(tall, thin);
  for (Eigen::Index j = 0; j < thin; ++j)
    for (Eigen::Index i = 0; i < tall; ++i) gaussian(i, j) = rng.normal();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(gaussian);
  Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(tall, thin);
  // Without this sign fix Q is not uniformly (Haar) distributed.
  const Eigen::MatrixXd r = qr.matrixQR().topRows(thin).triangularView<Eigen::Upper>();
  for (Eigen::Index j = 0; j < thin; ++j)
    if (r(j, j) < 0.0) q.col(j) = -q.col(j);
  if (rows >= cols)
    weights = (gain * q).cast<float>();
  else
    weights = (gain * q.transpose()).cast<float>();
}

}  // namespace rdsim::nn
