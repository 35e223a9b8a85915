// rdsim._rdsim.train: `rdsim train` in this process, a Trainer (rdsim/training/trainer.hpp) driven
// update by update with the GIL released, Python's signal handlers run between updates.
#include <csignal>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/training/trainer.hpp"

namespace rdsim::python {
namespace {

py::dict result_dict(const TrainResult& r) {
  py::dict d;
  d["run_dir"] = r.run_dir;
  d["model_path"] = r.model_path;
  d["checkpoint_path"] = r.checkpoint_path;
  d["timesteps"] = r.timesteps;
  d["total_timesteps"] = r.total_timesteps;
  d["episodes"] = r.episodes;
  d["updates"] = r.updates;
  d["window_episodes"] = r.stats.count;
  d["mean_return"] = r.stats.mean_return;
  d["min_return"] = r.stats.min_return;
  d["max_return"] = r.stats.max_return;
  d["mean_length"] = r.stats.mean_length;
  d["success_rate"] = r.stats.success_rate;
  d["wall_time"] = r.wall_time;
  d["stop_signal"] = r.stop_signal;
  return d;
}

// Python's signal handlers, run now (the GIL held). An exception one raises (KeyboardInterrupt from
// the default SIGINT handler) asks the trainer to stop as Ctrl-C does in `rdsim train`; it is kept
// in `pending` (the first only) for the caller to raise once the checkpoint is saved.
void check_signals(Trainer& trainer, py::object& pending) {
  if (PyErr_CheckSignals() == 0) return;
  py::error_already_set raised;  // takes the exception out of the interpreter
  if (pending.is_none()) pending = raised.value();
  trainer.request_stop(SIGINT);
}

// Runs one training run; returns (result dict, the exception a signal handler raised or None).
// Settings come checked and converted by rdsim/training.py: overrides as (option, key, text)
// (TrainerSettings::overrides), threads an int or None, max_memory_gb a float or None.
py::tuple train(const std::string& config_path, const std::string& config_json, const std::string& resume_dir,
                const py::list& overrides, const py::object& threads, bool overwrite, const py::object& max_memory_gb, bool quiet,
                const std::string& dashboard) {
  TrainerSettings s;
  s.config_path = config_path;
  if (!config_json.empty()) {
    s.config = nlohmann::json::parse(config_json, nullptr, /*allow_exceptions=*/false);
    if (s.config.is_discarded()) throw Error("rdsim.train: config: expected a dict of JSON values");
  }
  s.resume_dir = resume_dir;
  for (const py::handle& o : overrides) {
    const auto t = o.cast<py::tuple>();  // (option, key, text)
    s.overrides.push_back({t[0].cast<std::string>(), t[1].cast<std::string>(), t[2].cast<std::string>()});
  }
  if (!threads.is_none()) s.threads = threads.cast<int>();
  s.overwrite = overwrite;
  if (!max_memory_gb.is_none()) s.max_memory_gb = max_memory_gb.cast<double>();
  s.quiet = quiet;
  s.dashboard = dashboard;
  s.handle_signals = false;  // Python owns SIGINT: check_signals() turns it into request_stop
  s.names.python = true;     // messages name rdsim.train's keyword arguments, not the command's flags

  Trainer trainer(std::move(s));
  py::object pending = py::none();
  {
    py::gil_scoped_release unlocked;
    trainer.start();
  }
  while (true) {
    check_signals(trainer, pending);  // a Ctrl-C during start() or the update before stops the run here
    bool more = false;
    {
      py::gil_scoped_release unlocked;
      more = trainer.update();
    }
    if (!more) break;
  }
  TrainResult result;
  {
    py::gil_scoped_release unlocked;
    result = trainer.finish();
    // The progress line and the summary are C stdio (as in the CLI): out before Python prints again.
    std::fflush(stdout);
    std::fflush(stderr);
  }
  return py::make_tuple(result_dict(result), pending);
}

}  // namespace

void bind_train(py::module_& m) {
  m.def("train", &train, py::arg("config_path"), py::arg("config_json"), py::arg("resume_dir"), py::arg("overrides"),
        py::arg("threads"), py::arg("overwrite"), py::arg("max_memory_gb"), py::arg("quiet"), py::arg("dashboard"),
        "One `rdsim train` run in this process (use rdsim.train): (result dict, the exception that stopped it or None).");
}

}  // namespace rdsim::python
