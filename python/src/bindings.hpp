#pragma once
// The pieces of rdsim._rdsim, one file each: module.cpp calls every bind_*().
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"

namespace rdsim::python {

namespace py = pybind11;

void bind_env(py::module_& m);
void bind_vec_env(py::module_& m);
void bind_model(py::module_& m);
void bind_train(py::module_& m);
void bind_sim(py::module_& m);

// An EnvConfig from an env name and Python keyword options (the "env" keys of a config), read by
// the same ConfigReader rules and messages as a config file; `where` names the caller in messages.
EnvConfig env_config_from_options(const std::string& name, const py::dict& options, const std::string& where);
// to_json(EnvConfig) as JSON text (the package turns it into a dict).
std::string env_config_json(const EnvConfig& config);

// The name of a Python object's type ("float", "str") for messages.
inline std::string type_name(const py::handle& h) { return py::str(py::type::handle_of(h).attr("__name__")).cast<std::string>(); }

// A Python seed (None or an integer in [0, 2^64 - 1]); rdsim::Error naming `where` otherwise.
std::optional<std::uint64_t> read_seed(const py::object& seed, const std::string& where);

// The Spec as a dict: observation dtype/shape/vector_size/low/high/parts, action kind/n/low/high,
// max_episode_steps, control_dt, goal.
py::dict spec_dict(const Spec& spec);
// A goal env's layout and reward (core/goal_layout.hpp) as the dict spec_dict's "goal" holds; None
// for other envs.
py::object goal_dict(const GoalLayout& goal);

// NumPy storage for one observation of `space` (`batch` > 0: a batch of them, a leading axis) and
// where to write the first (taken with the GIL held). `object` is the space's array (an image or a
// vector), or for an image with a vector beside it (ObservationSpace::vector_size) the pair
// (image bytes or None, values: value_count() floats each), which the package's spaces.py turns
// into a goal dict.
struct PyObservation {
  py::object object;
  ObservationOut out;
};
PyObservation py_observation(const ObservationSpace& space, int batch = 0);
// Where observation `row` of a batch that starts at `first` lies.
ObservationOut observation_row(ObservationOut first, const ObservationSpace& space, int row);
// A copy of what py_observation made (an array, or the pair; None stays None).
py::object copy_observation_object(const py::handle& observation);

// Converts one action (a Python int / NumPy integer for Discrete, a float array for Box) after
// checking its type, shape, range and finiteness; rdsim::Error with a one-line message otherwise.
void read_action(const ActionSpace& space, const py::handle& action, Action& out);
// The same for a batch: an integer array (n,) or a float array (n, dim). `out` holds n actions.
void read_actions(const ActionSpace& space, const py::handle& actions, std::vector<Action>& out);

}  // namespace rdsim::python
