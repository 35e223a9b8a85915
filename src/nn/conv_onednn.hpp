#pragma once
#include <Eigen/Core>

#include "rdsim/nn/conv.hpp"

// Conv2d on oneDNN's own convolution kernels (src/nn/conv_onednn.cpp), the path of the oneDNN
// backend; Eigen's backend keeps the im2col products of src/nn/conv.cpp. Same contracts as
// Conv2d::forward and Conv2d::backward, which check the sizes before calling these.
namespace rdsim::nn::onednn_conv {

void forward(const Conv2d& conv, const Eigen::MatrixXf& x, Eigen::MatrixXf& y, ConvKernels& kernels);
void backward(Conv2d& conv, const Eigen::MatrixXf& x, const Eigen::MatrixXf& grad_y, Eigen::MatrixXf* grad_x,
              ConvKernels& kernels);

}  // namespace rdsim::nn::onednn_conv
