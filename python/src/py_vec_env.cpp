// rdsim._rdsim.VecEnv: the C++ VecEnv (N envs stepped together by worker threads or processes,
// automatic reset in the same step) driven from Python. The package's rdsim.make_vec wraps it in a
// gymnasium.vector.VectorEnv (python/rdsim/vector.py).
//
// Memory: observations are the VecEnv's own batch (the envs write into it, Env::step_into), seen
// from Python as a NumPy array without a copy; rewards, terminations, truncations, the info flags and
// the final observations of ended episodes are NumPy arrays this object allocates once and fills
// after each step. Nothing per env is a Python object. The GIL is released while the envs step.
// results() builds the tuple a Gymnasium step returns (copies of these arrays, or the arrays
// themselves) in one call.
#include <cstring>
#include <memory>

#include "background_job.hpp"
#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/registry.hpp"
// The one file of the package that includes the VecEnv header (its path may move with the library).
#include "rdsim/vecenv/vec_env.hpp"

namespace rdsim::python {
namespace {

EnvWorkers read_workers(const std::string& workers, const EnvConfig& config, const std::string& where) {
  if (workers == "auto") return auto_env_workers(config);
  if (workers == "threads") return EnvWorkers::threads;
  if (workers == "processes") return EnvWorkers::processes;
  throw Error(where + ": env_workers: expected one of auto, threads, processes, got \"" + one_line(workers, 60) + "\"");
}

class PyVecEnv {
public:
  PyVecEnv(const std::string& name, const py::dict& options, const std::string& where, int num_envs, int num_threads,
           std::uint64_t seed, const std::string& workers)
      : where_(where), config_(env_config_from_options(name, options, where)) {
    if (num_envs < 1 || num_envs > 4096)
      throw Error(where + ": num_envs: expected an integer in [1, 4096], got " + std::to_string(num_envs));
    if (num_threads < 1 || num_threads > 1024)
      throw Error(where + ": num_threads: expected an integer in [1, 1024], got " + std::to_string(num_threads));
    const EnvWorkers kind = read_workers(workers, config_, where);
    {
      py::gil_scoped_release unlocked;
      std::vector<std::unique_ptr<Env>> envs;
      for (int i = 0; i < num_envs; ++i) envs.push_back(make_env(config_));
      vec_ = std::make_shared<VecEnv>(std::move(envs), seed, 20, num_threads, kind);
    }
    spec_ = vec_->spec();
    n_ = num_envs;
    actions_.resize(static_cast<std::size_t>(n_));
    rewards_ = py::array_t<float>(n_);
    distance_ = py::array_t<float>(n_);
    for (auto* flags : {&terminations_, &truncations_, &success_, &collision_, &out_of_bounds_, &final_mask_})
      *flags = py::array_t<bool>(n_);
    PyObservation final_observations = py_observation(spec_.observation, n_);
    final_observations_ = final_observations.object;
    ones_ = py::array_t<bool>(n_);
    std::fill_n(ones_.mutable_data(), n_, true);
    info_arrays_ = {InfoArray{py::str("success"), py::str("_success"), success_},
                    InfoArray{py::str("collision"), py::str("_collision"), collision_},
                    InfoArray{py::str("out_of_bounds"), py::str("_out_of_bounds"), out_of_bounds_},
                    InfoArray{py::str("distance"), py::str("_distance"), distance_}};
    // Raw pointers, taken here with the GIL held: run_step() writes through them without it.
    out_ = {rewards_.mutable_data(), distance_.mutable_data(), terminations_.mutable_data(), truncations_.mutable_data(),
            success_.mutable_data(), collision_.mutable_data(), out_of_bounds_.mutable_data(), final_mask_.mutable_data(),
            final_observations.out};
  }

  ~PyVecEnv() {
    // A step begun with step_async finishes before the envs go.
    try {
      if (job_.busy()) job_.wait();
    } catch (...) {
    }
  }

  int size() const { return n_; }
  int num_threads() const { return vec_ ? vec_->num_threads() : 0; }
  bool processes() const { return vec_ && vec_->processes(); }
  long long timesteps() const { return vec_ ? vec_->timesteps() : 0; }
  py::dict spec() const { return spec_dict(spec_); }
  std::string config() const { return env_config_json(config_); }
  bool closed() const { return !vec_; }

  // The VecEnv's observation batch as an array (num_envs, *observation shape), no copy. It keeps
  // the VecEnv's memory alive for as long as it exists (after close() too).
  // For an image with a vector beside it, the pair (image bytes or None, values) as py_observation's.
  py::object observations() {
    VecEnv& vec = open();
    const ObservationBatch& b = vec.observations();
    const ObservationSpace& space = spec_.observation;
    std::vector<py::ssize_t> shape{n_};
    for (int d : space.shape) shape.push_back(d);
    auto* keep = new std::shared_ptr<VecEnv>(vec_);
    py::capsule owner(keep, [](void* p) { delete static_cast<std::shared_ptr<VecEnv>*>(p); });
    if (space.vector_size == 0) {
      if (b.type == ObsType::Float32) return py::array_t<float>(shape, b.values.data(), owner);
      return py::array_t<std::uint8_t>(shape, b.pixels.data(), owner);
    }
    py::array_t<float> values(std::vector<py::ssize_t>{n_, space.value_count()}, b.values.data(), owner);
    if (b.type == ObsType::Float32) return py::make_tuple(py::none(), values);
    return py::make_tuple(py::array_t<std::uint8_t>(shape, b.pixels.data(), owner), values);
  }

  void reset(const py::object& seed) {
    VecEnv& vec = idle();
    const auto s = read_seed(seed, where_ + ": reset");
    if (!s) throw Error(where_ + ": reset: seed: expected an integer (the package draws one when none is given)");
    py::gil_scoped_release unlocked;
    vec.reset(*s);
    ended_ = 0;
  }

  // Returns how many episodes ended in the step (final_obs and final_info in results() say which).
  int step(const py::handle& actions) {
    idle();
    read_actions(spec_.action, actions, actions_);
    py::gil_scoped_release unlocked;
    run_step();
    return ended_;
  }

  void step_async(const py::handle& actions) {
    idle();
    read_actions(spec_.action, actions, actions_);
    job_.start([this] { run_step(); });
  }

  int step_wait() {
    open();
    if (!job_.busy()) throw Error(where_ + ": step_wait: no step was started (call step_async first)");
    py::gil_scoped_release unlocked;
    job_.wait();
    return ended_;
  }

  // The last step's (observations, rewards, terminations, truncations, infos): the tuple
  // gymnasium's VectorEnv.step returns in the same-step autoreset mode. infos: the four info
  // arrays and their all-true masks and, when episodes ended, final_obs (an object array: the
  // ended envs' last observations, None elsewhere), final_info and their masks. Built here in one
  // call because every Python call and object per step costs time beside the envs' own work
  // (tools/bench/python.sh --overhead). copy=false: the arrays this object overwrites next step.
  py::tuple results(bool copy) {
    idle();
    if (!observations_view_) observations_view_ = observations();
    py::dict infos;
    for (const InfoArray& info : info_arrays_) {
      infos[info.key] = fresh(info.array);  // a copy: final_info shares it when episodes end
      infos[info.mask_key] = ones_;
    }
    if (ended_ > 0) add_final(infos);
    if (!copy) return py::make_tuple(observations_view_, rewards_, terminations_, truncations_, infos);
    return py::make_tuple(copy_observation_object(observations_view_), fresh(rewards_), fresh(terminations_), fresh(truncations_),
                          infos);
  }

  void close() {
    observations_view_ = py::object();  // its capsule keeps the VecEnv alive
    py::gil_scoped_release unlocked;
    try {
      if (job_.busy()) job_.wait();
    } catch (...) {
      // The step's error was the caller's to see through step_wait; closing goes on.
    }
    vec_.reset();
  }

  py::array_t<float> rewards_, distance_;
  py::array_t<bool> terminations_, truncations_, success_, collision_, out_of_bounds_, final_mask_;
  py::object final_observations_;  // py_observation's object for n_ envs

private:
  // An info array of results() and the keys it goes by.
  struct InfoArray {
    py::str key, mask_key;
    py::array array;
  };

  // A new array with `array`'s shape, type and values (C-contiguous, as every array here is).
  static py::array fresh(const py::handle& handle) {
    const auto& array = py::reinterpret_borrow<py::array>(handle);
    py::array copy(array.dtype(), std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()));
    std::memcpy(copy.mutable_data(), array.data(), static_cast<std::size_t>(array.nbytes()));
    return copy;
  }

  // results()'s final_obs, final_info and their masks (a copy of final_mask).
  void add_final(py::dict& infos) {
    py::array mask = fresh(final_mask_);
    const bool* ended = final_mask_.data();
    py::array final_obs(py::dtype("O"), std::vector<py::ssize_t>{n_});
    auto** slots = static_cast<PyObject**>(final_obs.mutable_data());
    for (int i = 0; i < n_; ++i) {
      py::object entry = py::none();
      if (ended[i]) entry = final_row(i);
      Py_XDECREF(slots[i]);  // numpy fills a new object array with None (or NULL)
      slots[i] = entry.release().ptr();
    }
    py::dict final_info;
    for (const InfoArray& info : info_arrays_) {
      final_info[info.key] = infos[info.key];  // the ended episodes' last infos (a reset adds none)
      final_info[info.mask_key] = mask;
    }
    infos["final_obs"] = final_obs;
    infos["_final_obs"] = mask;
    infos["final_info"] = final_info;
    infos["_final_info"] = mask;
  }

  // A copy of env i's final observation (an array, or the pair (image bytes or None, values)).
  py::object final_row(int i) const {
    const py::int_ row(i);
    if (!py::isinstance<py::tuple>(final_observations_)) return copy_observation_object(final_observations_[row]);
    const auto pair = py::reinterpret_borrow<py::tuple>(final_observations_);
    return copy_observation_object(
        py::make_tuple(pair[0].is_none() ? py::object(py::none()) : py::object(pair[0][row]), pair[1][row]));
  }

  VecEnv& open() {
    if (!vec_) throw Error(where_ + ": the vector env is closed");
    return *vec_;
  }
  VecEnv& idle() {
    VecEnv& vec = open();
    if (job_.busy()) throw Error(where_ + ": a step started with step_async is running: call step_wait first");
    return vec;
  }

  // Steps every env, writes the results into the arrays and counts the ended episodes. Runs
  // without the GIL: it touches only C++ objects and the arrays' memory, which this object owns.
  void run_step() {
    const std::vector<EnvStep>& steps = vec_->step(actions_);
    int ended = 0;
    for (int i = 0; i < n_; ++i) {
      const EnvStep& s = steps[static_cast<std::size_t>(i)];
      out_.reward[i] = s.reward;
      out_.terminated[i] = s.terminated;
      out_.truncated[i] = s.truncated;
      out_.success[i] = s.info.success;
      out_.collision[i] = s.info.collision;
      out_.out_of_bounds[i] = s.info.out_of_bounds;
      out_.distance[i] = s.info.distance;
      out_.ended[i] = s.done();
      if (!s.done()) continue;
      ++ended;
      copy_observation(s.final_observation, spec_.observation, observation_row(out_.final_observation, spec_.observation, i));
    }
    ended_ = ended;
  }

  // Where run_step() writes (the arrays' memory).
  struct Outputs {
    float *reward, *distance;
    bool *terminated, *truncated, *success, *collision, *out_of_bounds, *ended;
    ObservationOut final_observation;
  };

  std::string where_;
  EnvConfig config_;
  std::shared_ptr<VecEnv> vec_;
  Spec spec_;
  int n_ = 0;
  std::vector<Action> actions_;
  Outputs out_{};
  BackgroundJob job_;
  py::array_t<bool> ones_;         // the info masks: every env has every info key
  std::vector<InfoArray> info_arrays_;
  py::object observations_view_;   // observations(), made by the first results()
  int ended_ = 0;                  // episodes ended in the last step (run_step writes it)
};

}  // namespace

void bind_vec_env(py::module_& m) {
  py::class_<PyVecEnv>(m, "VecEnv", "The C++ VecEnv (use rdsim.make_vec, which wraps it in a gymnasium VectorEnv).")
      .def(py::init<const std::string&, const py::dict&, const std::string&, int, int, std::uint64_t, const std::string&>(),
           py::arg("name"), py::arg("options"), py::arg("where"), py::arg("num_envs"), py::arg("num_threads"),
           py::arg("seed"), py::arg("env_workers"))
      .def_property_readonly("num_envs", &PyVecEnv::size)
      .def_property_readonly("num_threads", &PyVecEnv::num_threads)
      .def_property_readonly("processes", &PyVecEnv::processes)
      .def_property_readonly("timesteps", &PyVecEnv::timesteps)
      .def_property_readonly("spec", &PyVecEnv::spec)
      .def_property_readonly("config_json", &PyVecEnv::config)
      .def_property_readonly("closed", &PyVecEnv::closed)
      .def("observations", &PyVecEnv::observations)
      .def("reset", &PyVecEnv::reset, py::arg("seed"))
      .def("step", &PyVecEnv::step, py::arg("actions"))
      .def("step_async", &PyVecEnv::step_async, py::arg("actions"))
      .def("step_wait", &PyVecEnv::step_wait)
      .def("results", &PyVecEnv::results, py::arg("copy"))
      .def("close", &PyVecEnv::close)
      .def_readonly("rewards", &PyVecEnv::rewards_)
      .def_readonly("terminations", &PyVecEnv::terminations_)
      .def_readonly("truncations", &PyVecEnv::truncations_)
      .def_readonly("success", &PyVecEnv::success_)
      .def_readonly("collision", &PyVecEnv::collision_)
      .def_readonly("out_of_bounds", &PyVecEnv::out_of_bounds_)
      .def_readonly("distance", &PyVecEnv::distance_)
      .def_readonly("final_mask", &PyVecEnv::final_mask_)
      .def_readonly("final_observations", &PyVecEnv::final_observations_);

  m.def(
      "env_seed",
      [](std::uint64_t seed, int i) {
        return Rng::derive(seed, rng_stream::env_base + static_cast<std::uint64_t>(i)).next_u64();
      },
      py::arg("seed"), py::arg("index"),
      "The seed of env `index`'s first episode in a vector env reset with `seed` (as the C++ VecEnv derives it).");
}

}  // namespace rdsim::python
