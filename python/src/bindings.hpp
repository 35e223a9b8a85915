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

// The Spec as a dict: observation dtype/shape/low/high, action kind/n/low/high, max_episode_steps, control_dt.
py::dict spec_dict(const Spec& spec);
// A goal env's layout and reward (core/goal_layout.hpp) as the dict spec_dict's "goal" holds; None
// for other envs.
py::object goal_dict(const GoalLayout& goal);

// Empty NumPy array shaped like one observation (`batch` > 0: batch x observation).
py::array observation_array(const ObservationSpace& space, int batch = 0);
// Where to write an observation into `array` (its first element; call with the GIL held).
ObservationOut observation_out(py::array& array);

// Converts one action (a Python int / NumPy integer for Discrete, a float array for Box) after
// checking its type, shape, range and finiteness; rdsim::Error with a one-line message otherwise.
void read_action(const ActionSpace& space, const py::handle& action, Action& out);
// The same for a batch: an integer array (n,) or a float array (n, dim). `out` holds n actions.
void read_actions(const ActionSpace& space, const py::handle& actions, std::vector<Action>& out);

}  // namespace rdsim::python
