// rdsim._rdsim: the compiled half of the rdsim Python package (python/rdsim/ is the other half).
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim::python {
namespace {

// (name, description, supports_pixels, resolved default config as JSON text)
// of every env.
py::list registry() {
  py::list out;
  for (const EnvEntry& e : env_registry())
    out.append(py::make_tuple(e.name, e.description, e.supports_pixels, to_json(default_env_config(e.name)).dump()));
  return out;
}

// GoalLayout::compute_reward for a spec's "goal" dict: rows of `achieved` and `desired` (n x 3 points,
// or one row) -> n rewards (float32), the env's own reward for each pair.
py::array_t<float> compute_reward(const py::dict& goal, const py::array& achieved, const py::array& desired) {
  GoalLayout g;
  g.points = goal["points"].cast<int>();
  g.distance_threshold = goal["distance_threshold"].cast<float>();
  const std::optional<GoalReward> reward = goal_reward_from_string(goal["reward"].cast<std::string>());
  if (!reward) throw Error("compute_reward: goal[\"reward\"]: expected sparse, partial or dense");
  g.reward = *reward;
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(achieved);
  const auto d = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(desired);
  const auto size = static_cast<py::ssize_t>(g.goal_size());
  if (!a || !d || a.ndim() < 1 || a.shape(a.ndim() - 1) != size || d.ndim() != a.ndim() || d.size() != a.size())
    throw Error("compute_reward: achieved_goal and desired_goal must be float arrays of the same shape whose last "
                "axis has " + std::to_string(size) + " values (" + std::to_string(g.points) + " points x 3)");
  const auto n = static_cast<int>(a.size() / size);
  py::array_t<float> out(n);
  g.compute_reward(a.data(), d.data(), n, out.mutable_data());
  py::tuple shape(a.ndim() - 1);  // the leading axes (none for one pair: a 0-d array)
  for (py::ssize_t i = 0; i + 1 < a.ndim(); ++i) shape[static_cast<std::size_t>(i)] = a.shape(i);
  return out.attr("reshape")(shape).cast<py::array_t<float>>();
}

}  // namespace
}  // namespace rdsim::python

PYBIND11_MODULE(_rdsim, m) {
  namespace py = pybind11;
  using namespace rdsim::python;
  m.doc() = "rdsim's C++ envs, vector env and models (use the rdsim package, not this module)";
  // rdsim::Error -> rdsim.Error (a subclass of Exception) carrying the CLI's one-line message.
  py::register_exception<rdsim::Error>(m, "Error", PyExc_Exception);
  m.attr("__version__") = RDSIM_VERSION;
  m.attr("source_dir") = RDSIM_SOURCE_DIR;
  m.def("registry", &registry,
        "Every registered env: (name, description, supports_pixels, defaults JSON).");
  m.def("compute_reward", &compute_reward, py::arg("goal"), py::arg("achieved_goal"), py::arg("desired_goal"),
        "A goal env's rewards for (achieved, desired) goal pairs, batched over the leading axes");
  bind_env(m);
  bind_vec_env(m);
  bind_model(m);
  bind_train(m);
  bind_sim(m);
}
