// rdsim._rdsim.Env: one rdsim::Env (made by the registry from keyword options), stepped from Python.
// The package's rdsim.make wraps it in a gymnasium.Env (python/rdsim/env.py).
#include <memory>
#include <optional>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim::python {

// A Python seed (None or an integer in [0, 2^64 - 1]) for Env::reset; rdsim::Error otherwise.
std::optional<std::uint64_t> read_seed(const py::object& seed, const std::string& where) {
  if (seed.is_none()) return std::nullopt;
  const std::string what = where + ": seed: expected None or an integer in [0, 2^64 - 1]";
  if (py::isinstance<py::bool_>(seed)) throw Error(what + ", got a bool");
  PyObject* index = PyNumber_Index(seed.ptr());  // Python and NumPy integers; not floats
  if (!index) {
    PyErr_Clear();
    throw Error(what + ", got a Python " + type_name(seed));
  }
  const py::int_ value = py::reinterpret_steal<py::int_>(index);
  const unsigned long long v = PyLong_AsUnsignedLongLong(value.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    throw Error(what + ", got " + py::str(value).cast<std::string>());
  }
  return static_cast<std::uint64_t>(v);
}

namespace {

class PyEnv {
public:
  PyEnv(const std::string& name, const py::dict& options, const std::string& where)
      : where_(where), config_(env_config_from_options(name, options, where)), env_(make_env(config_)), spec_(env_->spec()) {}

  py::dict spec() const { return spec_dict(spec_); }
  std::string config() const { return env_config_json(config_); }
  bool closed() const { return !env_; }

  py::object reset(const py::object& seed) {
    Env& env = open();
    const auto s = read_seed(seed, where_ + ": reset");
    PyObservation obs = py_observation(spec_.observation);
    {
      py::gil_scoped_release unlocked;
      env.reset_into(obs.out, s);
    }
    return obs.object;
  }

  // (observation, reward, terminated, truncated, success, collision, out_of_bounds, distance)
  py::tuple step(const py::handle& action) {
    Env& env = open();
    read_action(spec_.action, action, action_);
    PyObservation obs = py_observation(spec_.observation);
    StepOutcome o;
    {
      py::gil_scoped_release unlocked;
      o = env.step_into(action_, obs.out);
    }
    return py::make_tuple(obs.object, o.reward, o.terminated, o.truncated, o.info.success, o.info.collision, o.info.out_of_bounds,
                          o.info.distance);
  }

  // An RGB frame (height, width, 3) when the env was made with render_mode "rgb_array", else None.
  py::object render() {
    Env& env = open();
    bool drawn = false;
    {
      py::gil_scoped_release unlocked;
      drawn = env.render(frame_);
    }
    if (!drawn) return py::none();
    py::array_t<std::uint8_t> a({frame_.height, frame_.width, 3});
    std::copy(frame_.rgb.begin(), frame_.rgb.end(), a.mutable_data());
    return a;
  }

  void close() {
    py::gil_scoped_release unlocked;
    env_.reset();
  }

private:
  Env& open() {
    if (!env_) throw Error(where_ + ": the env is closed");
    return *env_;
  }

  std::string where_;
  EnvConfig config_;
  std::unique_ptr<Env> env_;
  Spec spec_;
  Action action_;
  Image frame_;
};

}  // namespace

void bind_env(py::module_& m) {
  py::class_<PyEnv>(m, "Env", "One rdsim env (use rdsim.make, which wraps it in a gymnasium.Env).")
      .def(py::init<const std::string&, const py::dict&, const std::string&>(), py::arg("name"), py::arg("options"),
           py::arg("where"))
      .def_property_readonly("spec", &PyEnv::spec)
      .def_property_readonly("config_json", &PyEnv::config)
      .def_property_readonly("closed", &PyEnv::closed)
      .def("reset", &PyEnv::reset, py::arg("seed") = py::none())
      .def("step", &PyEnv::step, py::arg("action"))
      .def("render", &PyEnv::render)
      .def("close", &PyEnv::close);
}

}  // namespace rdsim::python
