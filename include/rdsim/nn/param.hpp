#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

// Trainable tensors as seen by optimisers, gradient clipping and serialisation.
namespace rdsim::nn {

// A value matrix and its gradient (same shape), owned together. Networks hold their weights
// in Tensors; a free parameter such as a Gaussian policy's log-std is simply a Tensor (dims x 1).
struct Tensor {
  Eigen::MatrixXf value;
  Eigen::MatrixXf grad;

  Tensor() = default;
  // Zero value and zero gradient of the given shape.
  Tensor(int rows, int cols);

  void zero_grad() { grad.setZero(); }
};

// A non-owning view of one trainable tensor. The pointers stay valid while the owner lives and
// is not moved or copied: take params() again after moving a network (e.g. into a vector).
struct Param {
  Eigen::MatrixXf* value = nullptr;
  Eigen::MatrixXf* grad = nullptr;
  std::string name;  // for error messages ("layer1.weight")
};

using ParamList = std::vector<Param>;

// A Param viewing `tensor`.
Param param_of(Tensor& tensor, std::string name);

// Appends the `weight` and `bias` Tensors of each layer, named "<prefix><i>.weight" and
// "<prefix><i>.bias" (a network's own layers: "layer0.weight", "conv1.bias", ...).
template <class Layer>
void append_layer_params(ParamList& list, std::vector<Layer>& layers, const std::string& prefix) {
  for (size_t i = 0; i < layers.size(); ++i) {
    const std::string name = prefix + std::to_string(i);
    list.push_back(param_of(layers[i].weight, name + ".weight"));
    list.push_back(param_of(layers[i].bias, name + ".bias"));
  }
}

// Appends a part's parameters with `prefix` before each name ("head.", "policy.").
void append_params(ParamList& list, ParamList part, const std::string& prefix);

// Sets every gradient in the list to zero.
void zero_grad(const ParamList& params);

// Total number of scalars in the list.
long long parameter_count(const ParamList& params);

// sqrt(sum of every squared gradient entry).
float global_grad_norm(const ParamList& params);

// Every value (or gradient) of the list as one vector: tensors in list order, each column-major.
// Search methods (ARS, CMA-ES) and trust-region steps (TRPO) work on parameters in this form.
Eigen::VectorXf flatten_values(const ParamList& params);
Eigen::VectorXf flatten_grads(const ParamList& params);
// Writes a vector of that layout back into the values; rdsim::Error when its length is not
// parameter_count(params).
void assign_values(const ParamList& params, const Eigen::Ref<const Eigen::VectorXf>& flat);

// Scales all gradients by max_norm / norm when the global norm exceeds max_norm (as the common
// baselines do, with a 1e-6 guard). Returns the global norm BEFORE clipping.
float clip_grad_norm(const ParamList& params, float max_norm);

}  // namespace rdsim::nn
