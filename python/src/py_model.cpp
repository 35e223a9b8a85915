// rdsim._rdsim.Model: a saved policy (model.bin / checkpoint.bin written by `rdsim train`), loaded as
// `rdsim replay` loads it, acting on batches of NumPy observations.
#include <cmath>
#include <sstream>

#include "bindings.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/training/saved_policy.hpp"
#include "rdsim/export/policy_export.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"

namespace rdsim::python {
namespace {

class PyModel {
public:
  explicit PyModel(const std::string& path) : path_(path) {
    py::gil_scoped_release unlocked;
    SavedPolicy saved = load_saved_policy(path);
    config_ = std::move(saved.config);
    spec_ = saved.spec;
    algo_ = std::move(saved.algorithm);
    rng_ = Rng::derive(config_.seed, rng_stream::evaluation);
  }

  std::string config() const { return to_json(config_).dump(); }
  py::dict spec() const { return spec_dict(spec_); }
  std::string algorithm() const { return config_.algorithm.name(); }

  // Actions for a batch of observations (n, *shape), or one observation (*shape) -> one action.
  py::object predict(const py::handle& observations, bool deterministic) {
    const ObservationSpace& space = spec_.observation;
    const bool floats = space.type == ObsType::Float32;
    py::array a = py::array::ensure(observations);
    if (!a) {
      PyErr_Clear();
      throw Error(path_ + ": predict: expected a NumPy array of observations");
    }
    const auto rank = static_cast<py::ssize_t>(space.shape.size());
    const bool single = a.ndim() == rank;
    bool shape_ok = a.ndim() == rank || a.ndim() == rank + 1;
    for (py::ssize_t d = 0; shape_ok && d < rank; ++d) shape_ok = a.shape(a.ndim() - rank + d) == space.shape[static_cast<std::size_t>(d)];
    const char kind = a.dtype().kind();
    const bool dtype_ok = floats ? (kind == 'f') : py::dtype(a.dtype()).is(py::dtype::of<std::uint8_t>());
    if (!shape_ok || !dtype_ok) {
      std::string shape;
      for (int d : space.shape) shape += std::to_string(d) + ", ";
      throw Error(path_ + ": predict: expected " + (floats ? "a float array" : "a uint8 array") + " of shape (n, " + shape.substr(0, shape.size() - 2) +
                  ") or (" + shape.substr(0, shape.size() - 2) + (rank == 1 ? ",)" : ")") + ", got " +
                  py::str(a.dtype()).cast<std::string>() + " of " + std::to_string(a.ndim()) + " dimensions");
    }
    const py::ssize_t n = single ? 1 : a.shape(0);
    const int size = space.size();
    std::vector<Action> actions(static_cast<std::size_t>(n));
    Observation obs;
    if (floats) {
      auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
      for (py::ssize_t k = 0; k < f.size(); ++k)
        if (!std::isfinite(f.data()[k])) throw Error(path_ + ": predict: observations must be finite");
      py::gil_scoped_release unlocked;
      for (py::ssize_t i = 0; i < n; ++i) {
        obs.values = Eigen::Map<const Eigen::VectorXf>(f.data() + i * size, size);
        actions[static_cast<std::size_t>(i)] = algo_->act(obs, deterministic, rng_);
      }
    } else {
      auto b = py::array_t<std::uint8_t, py::array::c_style>::ensure(a);
      py::gil_scoped_release unlocked;
      for (py::ssize_t i = 0; i < n; ++i) {
        obs.pixels.assign(b.data() + i * size, b.data() + (i + 1) * size);
        actions[static_cast<std::size_t>(i)] = algo_->act(obs, deterministic, rng_);
      }
    }
    if (spec_.action.discrete) {
      py::array_t<std::int64_t> out(n);
      for (py::ssize_t i = 0; i < n; ++i) out.mutable_data()[i] = actions[static_cast<std::size_t>(i)].index;
      if (single) return py::int_(out.data()[0]);
      return out;
    }
    const int dim = spec_.action.dim();
    py::array_t<float> out({n, static_cast<py::ssize_t>(dim)});
    for (py::ssize_t i = 0; i < n; ++i)
      std::copy(actions[static_cast<std::size_t>(i)].values.data(), actions[static_cast<std::size_t>(i)].values.data() + dim,
                out.mutable_data() + i * dim);
    if (single) return out[py::int_(0)];
    return out;
  }

  // `rdsim export PATH --onnx out`: returns the file's size in bytes.
  long long export_onnx(const std::string& out) const {
    py::gil_scoped_release unlocked;
    return rdsim::export_onnx(path_, out).bytes;
  }

private:
  std::string path_;
  TrainConfig config_;
  Spec spec_;
  std::unique_ptr<Algorithm> algo_;
  Rng rng_;
};

}  // namespace

void bind_model(py::module_& m) {
  py::class_<PyModel>(m, "Model", "A saved rdsim policy (use rdsim.load_model).")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def_property_readonly("config_json", &PyModel::config)
      .def_property_readonly("spec", &PyModel::spec)
      .def_property_readonly("algorithm", &PyModel::algorithm)
      .def("predict", &PyModel::predict, py::arg("observations"), py::arg("deterministic") = true)
      .def("export_onnx", &PyModel::export_onnx, py::arg("path"));
}

}  // namespace rdsim::python
