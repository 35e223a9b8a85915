#pragma once
#include <Eigen/Core>
#include <memory>

#include "rdsim/nn/param.hpp"

// The one interface of rdsim's trainable networks (nn::Mlp, nn::Cnn), so an algorithm holds "a
// network" and never asks which kind. Batches are stored one column per sample (features x batch).
namespace rdsim::nn {

class Network {
public:
  virtual ~Network() = default;

  // Training forward pass on (input_size x batch); caches what backward() needs.
  // The returned reference stays valid until the next forward().
  virtual const Eigen::MatrixXf& forward(const Eigen::MatrixXf& x) = 0;

  // forward() for a caller that keeps x alive and unchanged until its backward(): the network may
  // keep a reference to x instead of a copy (a Cnn's input, a batch of images, is megabytes).
  virtual const Eigen::MatrixXf& forward_borrowing(const Eigen::MatrixXf& x) { return forward(x); }

  // Back-propagates dLoss/dOutput (output_size x batch) of the LAST forward() batch.
  // ACCUMULATES (+=) into the parameter gradients, so several losses can share a network.
  // Returns dLoss/dInput (input_size x batch), or an empty matrix when !need_input_grad (which
  // skips the first layer's input gradient).
  virtual Eigen::MatrixXf backward(const Eigen::MatrixXf& grad_output, bool need_input_grad = true) = 0;

  // Inference on any batch (a single column for acting) with its own buffers: the training cache
  // stays untouched and nothing is allocated after the first call of a given batch size.
  // The returned reference stays valid until the next infer().
  virtual const Eigen::MatrixXf& infer(const Eigen::MatrixXf& x) = 0;

  // Allocating, const inference (for code that holds a const network).
  virtual Eigen::MatrixXf evaluate(const Eigen::MatrixXf& x) const = 0;

  // Every trainable tensor, named; this order is the serialisation order.
  virtual ParamList params() = 0;

  virtual int input_size() const = 0;
  virtual int output_size() const = 0;

  // A copy of the same kind (a DQN target network): weights, shape and caches.
  virtual std::unique_ptr<Network> clone() const = 0;

  // Sets every parameter gradient to zero.
  void zero_grad();
  // Copies the parameter values (not gradients or caches) of a network with the same parameters
  // (names and shapes, in order), e.g. into a DQN target network. rdsim::Error when they differ;
  // then nothing is written.
  void copy_values_from(const Network& other);
  // value = tau * other + (1 - tau) * value (Polyak averaging); the same rule for `other`.
  void blend_values_from(const Network& other, float tau);

protected:
  // Copies only through a concrete type (clone()), never by slicing a Network.
  Network() = default;
  Network(const Network&) = default;
  Network(Network&&) = default;
  Network& operator=(const Network&) = default;
  Network& operator=(Network&&) = default;
};

}  // namespace rdsim::nn
