// rdsim._rdsim: the compiled half of the rdsim Python package (python/rdsim/ is the other half).
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim::python {
namespace {

// (name, description, supports_pixels, resolved default config as JSON text) of every env.
py::list registry() {
  py::list out;
  for (const EnvEntry& e : env_registry())
    out.append(py::make_tuple(e.name, e.description, e.supports_pixels, to_json(default_env_config(e.name)).dump()));
  return out;
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
  m.def("registry", &registry, "Every registered env: (name, description, supports_pixels, defaults JSON).");
  bind_env(m);
  bind_vec_env(m);
  bind_model(m);
  bind_train(m);
  bind_sim(m);
}
