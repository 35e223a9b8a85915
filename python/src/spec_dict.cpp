// Spec -> the dict the Python package builds Gymnasium spaces from; observation arrays and views.
#include <cstring>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::python {
namespace {

py::array_t<float> float_array(const Eigen::VectorXf& v) {
  py::array_t<float> a(v.size());
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

py::tuple shape_tuple(const std::vector<int>& shape) {
  py::tuple t(shape.size());
  for (std::size_t i = 0; i < shape.size(); ++i) t[i] = shape[i];
  return t;
}

}  // namespace

py::dict spec_dict(const Spec& spec) {
  py::dict d;
  d["env_name"] = spec.env_name;
  const ObservationSpace& o = spec.observation;
  d["observation_dtype"] = o.type == ObsType::Float32 ? "float32" : "uint8";
  d["observation_shape"] = shape_tuple(o.shape);
  d["observation_vector_size"] = o.vector_size;
  d["observation_low"] = float_array(o.low);
  d["observation_high"] = float_array(o.high);
  py::list parts;  // [(name, size), ...] (ObservationSpace::parts)
  for (const ObservationPart& p : o.parts) parts.append(py::make_tuple(p.name, p.size));
  d["observation_parts"] = parts;
  d["discrete"] = spec.action.discrete;
  d["n"] = spec.action.n;
  d["action_low"] = float_array(spec.action.low);
  d["action_high"] = float_array(spec.action.high);
  d["max_episode_steps"] = spec.max_episode_steps;
  d["control_dt"] = spec.control_dt;
  d["goal"] = goal_dict(spec.goal);
  return d;
}

py::object goal_dict(const GoalLayout& goal) {
  if (!goal.active()) return py::none();
  py::dict g;
  g["observation"] = goal.observation;
  g["points"] = goal.points;
  g["distance_threshold"] = goal.distance_threshold;
  g["reward"] = to_string(goal.reward);
  return g;
}

namespace {

template <class T>
py::array_t<T> batch_array(int batch, const std::vector<int>& shape) {
  std::vector<py::ssize_t> dims;
  if (batch > 0) dims.push_back(batch);
  for (int d : shape) dims.push_back(d);
  return py::array_t<T>(dims);
}

// A new array with `array`'s shape, type and values.
py::array copied(const py::array& array) {
  py::array copy(array.dtype(), std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()));
  std::memcpy(copy.mutable_data(), array.data(), static_cast<std::size_t>(array.nbytes()));
  return copy;
}

}  // namespace

PyObservation py_observation(const ObservationSpace& space, int batch) {
  if (space.vector_size == 0) {
    if (space.type == ObsType::Float32) {
      auto values = batch_array<float>(batch, space.shape);
      return {values, {values.mutable_data(), nullptr}};
    }
    auto pixels = batch_array<std::uint8_t>(batch, space.shape);
    return {pixels, {nullptr, pixels.mutable_data()}};
  }
  auto values = batch_array<float>(batch, {space.value_count()});
  if (space.type == ObsType::Float32) return {py::make_tuple(py::none(), values), {values.mutable_data(), nullptr}};
  auto pixels = batch_array<std::uint8_t>(batch, space.shape);
  return {py::make_tuple(pixels, values), {values.mutable_data(), pixels.mutable_data()}};
}

ObservationOut observation_row(ObservationOut first, const ObservationSpace& space, int row) {
  return {first.values ? first.values + static_cast<std::ptrdiff_t>(row) * space.value_count() : nullptr,
          first.pixels ? first.pixels + static_cast<std::ptrdiff_t>(row) * space.byte_count() : nullptr};
}

py::object copy_observation_object(const py::handle& observation) {
  if (!py::isinstance<py::tuple>(observation)) return copied(py::reinterpret_borrow<py::array>(observation));
  const auto pair = py::reinterpret_borrow<py::tuple>(observation);
  const py::object pixels = pair[0].is_none() ? py::none() : py::object(copied(pair[0].cast<py::array>()));
  return py::make_tuple(pixels, copied(pair[1].cast<py::array>()));
}

}  // namespace rdsim::python
