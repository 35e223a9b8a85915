#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rdsim/core/goal_layout.hpp"

// The one interface between environments and everything that drives them (algorithms, replay,
// benchmarks, the demonstration link). Gymnasium semantics: reset(seed) -> observation,
// step(action) -> {observation, reward, terminated, truncated, info}.
//
// Two ways to drive an Env, both always available:
//   plain      reset() / step() return the observation by value. What one-env callers use
//              (replay, tests, a remote link), and all an env must implement.
//   into       reset_into() / step_into() write the observation into memory the caller owns (a
//              column of VecEnv's batch, PufferLib style): no allocation, no copy per step, which
//              matters for pixel observations (64x64x3 = 12 KiB per step). The defaults call
//              reset()/step() and copy, so every Env supports them; an env overrides them (and
//              then implements reset()/step() through them) to skip that copy. Both paths must
//              give the same observations and results for the same calls.
namespace rdsim {

enum class ObsType { Float32, UInt8 };

// A named run of a Float32 vector observation's values: "effector_position", 3 values.
struct ObservationPart {
  std::string name;
  int size = 0;

  bool operator==(const ObservationPart&) const = default;
};

// What an observation looks like. Ground-truth observations are Float32 vectors (shape {n});
// pixel observations are UInt8 images (or Float32 stacks of colour, depth and segmentation:
// EnvConfig::image_channels) stored height x width x channels, row-major. A goal env's pixel
// observations also carry a Float32 vector beside the image (vector_size values: its achieved and
// desired goals), after a Float32 image's values in Observation::values.
struct ObservationSpace {
  ObsType type = ObsType::Float32;
  std::vector<int> shape;     // the vector's or the image's
  int vector_size = 0;        // Float32 values beside an image; 0 = none (every other space)
  Eigen::VectorXf low, high;  // per Float32 value (value_count()); UInt8 bytes are 0..255
  // What each value of a vector observation (or of the vector beside an image) is, in order,
  // covering every one once (names unique; a goal env's last two are "achieved_goal" and
  // "desired_goal"). The robot tasks name theirs (randomize.observation_noise_parts reads them);
  // empty = not named (images, classic control).
  std::vector<ObservationPart> parts;

  // Elements of `shape`: the vector's values or the image's pixels x channels.
  int size() const {
    int n = 1;
    for (int d : shape) n *= d;
    return n;
  }
  // Float32 values of one observation (Observation::values): a Float32 vector or image, then the
  // vector beside an image.
  int value_count() const { return (type == ObsType::Float32 ? size() : 0) + vector_size; }
  // UInt8 bytes of one observation (Observation::pixels).
  int byte_count() const { return type == ObsType::UInt8 ? size() : 0; }
  // A Float32 vector of `size` values without bounds or names.
  static ObservationSpace vector(int size) {
    ObservationSpace s;
    s.shape = {size};
    return s;
  }
  // Where part `name` starts and how many values it has; {-1, 0} when there is none.
  std::pair<int, int> part(const std::string& name) const;
  // The part names, comma separated (for messages).
  std::string part_names() const;
};

// Either Discrete(n) (discrete == true, n choices) or a continuous Box of `low.size()` dims.
struct ActionSpace {
  bool discrete = true;
  int n = 0;
  Eigen::VectorXf low, high;

  int dim() const { return discrete ? 1 : static_cast<int>(low.size()); }
};

struct Spec {
  std::string env_name;
  ObservationSpace observation;
  ActionSpace action;
  int max_episode_steps = 0;   // truncation limit
  double control_dt = 0.0;     // simulated seconds per env step (0 when not a physics env)
  // Goal-conditioned envs (core/goal_layout.hpp): how the Float32 observation splits into
  // observation / achieved_goal / desired_goal, and the reward of any pair. Inactive otherwise.
  GoalLayout goal{};
};

struct Action {
  int index = 0;            // for Discrete spaces
  Eigen::VectorXf values;   // for Box spaces

  static Action discrete(int i) { return Action{i, {}}; }
  static Action continuous(Eigen::VectorXf v) { return Action{0, std::move(v)}; }
};

struct Observation {
  Eigen::VectorXf values;              // Float32 values (ObservationSpace::value_count())
  std::vector<std::uint8_t> pixels;    // UInt8 images (HWC; ObservationSpace::byte_count())
};

// An RGB picture for people (Env::render), row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // height x width x 3
};

// Typed episode facts every reaching task reports; fields an env does not use keep defaults.
struct StepInfo {
  bool success = false;       // task solved on this step
  bool collision = false;     // robot touched a forbidden body
  bool out_of_bounds = false; // left the workspace
  float distance = 0.0f;      // task distance (e.g. end effector to target), metres
};

struct StepResult {
  Observation observation;
  float reward = 0.0f;
  bool terminated = false;  // the MDP ended (success, failure): do not bootstrap
  bool truncated = false;   // cut by the step limit: bootstrap from the value of `observation`
  StepInfo info;
};

// A step's result without its observation (step_into writes that into caller memory).
struct StepOutcome {
  float reward = 0.0f;
  bool terminated = false;
  bool truncated = false;
  StepInfo info;
};

// Caller-owned memory for one observation of a space: value_count() floats (`values`) and
// byte_count() bytes (`pixels`, HWC); a pointer whose count is 0 is null. It must stay valid for
// the duration of the call only.
struct ObservationOut {
  float* values = nullptr;
  std::uint8_t* pixels = nullptr;
};

// Copies `obs` into `out`; rdsim::Error when its size or type differs from `space`.
void copy_observation(const Observation& obs, const ObservationSpace& space, ObservationOut out);

// Storage for one observation of `space` (values or pixels sized) and a view of it.
Observation make_observation(const ObservationSpace& space);
ObservationOut observation_out(Observation& obs);

class Env {
public:
  virtual ~Env() = default;
  virtual const Spec& spec() const = 0;

  // Starts an episode. A seed re-seeds the env's generator; without one the stream continues,
  // so a sequence of resets after one seeded reset is reproducible too.
  virtual Observation reset(std::optional<std::uint64_t> seed = std::nullopt) = 0;
  // One control step. An action outside the action space (a Discrete index out of range, a Box
  // action of the wrong size) is an rdsim::Error, whether or not the episode has ended. Stepping
  // an episode that has ended (terminated or truncated), before reset(), is harmless: nothing
  // moves, and the result is the last observation with reward 0 and terminated = true.
  virtual StepResult step(const Action& action) = 0;

  // The same as reset()/step() with the observation written to `out` (see the top of this file).
  // Defaults: reset()/step() and copy_observation().
  virtual void reset_into(ObservationOut out, std::optional<std::uint64_t> seed = std::nullopt);
  virtual StepOutcome step_into(const Action& action, ObservationOut out);

  // Split-phase step, for envs whose step is mostly waiting (a RemoteEnv: one network round trip).
  // begin_step starts the step and returns true; the next call on the env must then be
  // finish_step, which waits for that step and returns exactly what step_into would have. An env
  // that cannot split a step returns false (the default) and the caller uses step_into. VecEnv
  // begins the steps of all the envs of a worker before it finishes any, so N remote envs cost
  // about one round trip per batch step instead of N, with the same results.
  virtual bool begin_step(const Action& /*action*/) { return false; }
  // Default: rdsim::Error (no env that returns false from begin_step gets this call).
  virtual StepOutcome finish_step(ObservationOut out);

  // Advances only the physics world by what one env step simulates, with no control,
  // observation or reward work: lets benchmarks show the env's own overhead.
  // Returns false for envs without a physics world.
  virtual bool step_physics_only() { return false; }
  // True when any thread may step this env, as long as one thread at a time does: it holds nothing
  // bound to a thread (a GL context) and does not split its steps (begin_step). VecEnv then lets
  // a worker that finished its own envs step another worker's remaining ones. Default: false.
  virtual bool steps_on_any_thread() const { return false; }
  // Draws the current state for people when the env was made with render_mode "rgb_array"
  // (EnvConfig::render_width x render_height, the main camera). Returns false otherwise.
  virtual bool render(Image& /*frame*/) { return false; }
};

// For an env that implements the "into" path itself: its reset()/step() are these (the
// observation goes into a freshly allocated Observation), so the two paths share one body.
Observation reset_through_into(Env& env, std::optional<std::uint64_t> seed);
StepResult step_through_into(Env& env, const Action& action);

// Any step written "into" caller memory as a StepResult: `step_into(out)` returns the StepOutcome
// and writes the observation into storage for `space` made here (step_through_into's body, also
// what RobotControl's commands return).
template <class StepInto>
StepResult step_result(const ObservationSpace& space, StepInto&& step_into) {
  StepResult r;
  r.observation = make_observation(space);
  const StepOutcome o = step_into(observation_out(r.observation));
  r.reward = o.reward;
  r.terminated = o.terminated;
  r.truncated = o.truncated;
  r.info = o.info;
  return r;
}

}  // namespace rdsim
