#pragma once
#include <Eigen/Core>
#include <string>

// Element-wise activations of the networks (MLP, CNN, actor-critic trunk), on batches stored one
// column per sample.
namespace rdsim::nn {

enum class Activation { Tanh, ReLU, Identity };

// "tanh", "relu", "identity" -> Activation; anything else throws rdsim::Error naming `where`.
Activation activation_from_string(const std::string& name, const std::string& where);
const char* to_string(Activation activation);

// z = activation(z), in place.
void activate(Eigen::MatrixXf& z, Activation activation);
// z = activation(z + bias), bias added to every column: one pass over z.
void bias_activate(Eigen::MatrixXf& z, const Eigen::Ref<const Eigen::VectorXf>& bias, Activation activation);
// dLoss/dz from dLoss/dy (in place), where y = activation(z) is what the forward pass kept.
void activation_backward(Eigen::MatrixXf& grad, const Eigen::MatrixXf& y, Activation activation);

}  // namespace rdsim::nn
