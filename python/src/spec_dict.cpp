// Spec -> the dict the Python package builds Gymnasium spaces from; observation arrays and views.
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

py::array observation_array(const ObservationSpace& space, int batch) {
  std::vector<py::ssize_t> shape;
  if (batch > 0) shape.push_back(batch);
  for (int d : space.shape) shape.push_back(d);
  if (space.type == ObsType::Float32) return py::array_t<float>(shape);
  return py::array_t<std::uint8_t>(shape);
}

ObservationOut observation_out(py::array& array) {
  void* base = array.mutable_data();
  if (array.dtype().is(py::dtype::of<float>())) return {static_cast<float*>(base), nullptr};
  return {nullptr, static_cast<std::uint8_t*>(base)};
}

}  // namespace rdsim::python
