#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env.hpp"

// Domain randomization of a robot env ("randomize": {...} in its config): what a real robot's
// body, sensors and controller add to the simulation, so that a policy does not rely on one set
// of exact, instant values. Every draw comes from the env's own streams, seeded by its reset seed
// (the same seed gives the same draws), is kept in its saved state (a resumed run continues
// bit-identically) and is made where the env runs (local or remote alike). Two parts:
//  - per episode, inside the env (envs/task_randomizer.hpp): masses, friction, joint damping,
//    drive gains, placements of the target and objects, and for raw-pixel observations the
//    camera, the colours and the light;
//  - per step, around the env (randomized(), below): observation noise and action latency.
namespace rdsim {

struct Randomization {
  // Per-episode factor ranges [lo, hi], each value drawn uniformly: [1, 1] (or [0, 0]) = none.
  std::vector<double> mass_scale{1.0, 1.0};      // each robot link's and object's mass and moments
  std::vector<double> friction_scale{1.0, 1.0};  // each object's friction, and the robot's (one factor)
  std::vector<double> joint_damping{0.0, 0.0};   // N m s/rad added to each joint's damping
  std::vector<double> gain_scale{1.0, 1.0};      // the drive's position and velocity gains (one factor each)
  double placement_noise = 0.0;                  // m: uniform +- in x and y on the target (goals) and objects
  // Raw-pixel observations' cameras (each camera its own draw), colours and light, per episode.
  double camera_shift = 0.0;  // m: uniform +- per axis on the camera's position
  double camera_turn = 0.0;   // deg: uniform +- on the view direction's yaw and pitch
  double camera_fov = 0.0;    // deg: uniform +- on the field of view
  double colour_noise = 0.0;  // uniform +- on each drawn part's r, g, b (in [0, 1])
  double light_turn = 0.0;    // deg: uniform +- on the light direction's yaw and pitch
  // Per step.
  double observation_noise = 0.0;  // standard deviation, in the observed values' own units
  // Per part of the observation (ObservationSpace::parts): its standard deviation instead.
  std::map<std::string, double> observation_noise_parts;
  int action_latency = 0;          // env steps
  bool random_latency = false;     // each episode's latency drawn from 0..action_latency
  bool observe_latency = false;    // the actions still to run appended to the observation
  int latency_slots = 0;           // observe_latency's action slots; 0 = action_latency

  // The per-step part (the randomized() wrapper) and the per-episode part (TaskRandomizer).
  bool per_step() const { return noisy() || action_latency > 0 || random_latency || observe_latency; }
  bool noisy() const { return observation_noise > 0.0 || !observation_noise_parts.empty(); }
  int queue_slots() const { return observe_latency ? (latency_slots > 0 ? latency_slots : action_latency) : 0; }
  bool per_episode() const { return varies_physics() || varies_view(); }
  bool varies_physics() const {
    return !is_one(mass_scale) || !is_one(friction_scale) || !is_zero(joint_damping) || !is_one(gain_scale) ||
           placement_noise > 0.0;
  }
  bool varies_view() const {
    return camera_shift > 0.0 || camera_turn > 0.0 || camera_fov > 0.0 || colour_noise > 0.0 || light_turn > 0.0;
  }

private:
  static bool is_one(const std::vector<double>& r) { return r.size() == 2 && r[0] == 1.0 && r[1] == 1.0; }
  static bool is_zero(const std::vector<double>& r) { return r.size() == 2 && r[0] == 0.0 && r[1] == 0.0; }
};

namespace config {
// A [lo, hi] range: two numbers, lo <= hi.
inline bool is_range(const std::vector<double>& r) { return r.size() == 2 && r[0] <= r[1]; }
}  // namespace config

template <class V, class C>
  requires config::Describes<C, Randomization>
void describe(V& v, C& c) {
  v.field("mass_scale", c.mass_scale, config::Range{0.01, 100.0},
          "[lo, hi]: each episode every robot link's and every object's mass (and moments of inertia) is scaled "
          "by its own factor drawn uniformly from this range; [1, 1] = none");
  v.field("friction_scale", c.friction_scale, config::Range{0.0, 100.0},
          "[lo, hi]: each episode every object's friction coefficient, and the robot's links' (one factor), is "
          "scaled by a factor drawn from this range (a contact's coefficient is the product of its two sides'); "
          "[1, 1] = none");
  v.field("joint_damping", c.joint_damping, config::Range{0.0, 1e6},
          "[lo, hi] N m s/rad (N s/m for prismatic joints): each episode every joint gets this much viscous "
          "damping, drawn per joint; [0, 0] = none");
  v.field("gain_scale", c.gain_scale, config::Range{0.01, 100.0},
          "[lo, hi]: each episode the joint drive's position gain and its velocity gain are scaled by one factor "
          "each drawn from this range (above 2x the position gain overshoots); [1, 1] = none");
  v.field("placement_noise", c.placement_noise, config::Range{0.0, 1.0},
          "m: each episode the target (the goals) and the objects are moved by up to this in x and y (uniform) "
          "from where the task put them, the objects by one offset and the goals by another (cubes keep apart, "
          "a stack's goals stay stacked); 0 = none");
  v.field("camera_shift", c.camera_shift, config::Range{0.0, 1.0},
          "m: each episode every camera of a raw-pixel observation moves by up to this along each world axis "
          "(uniform); 0 = none");
  v.field("camera_turn", c.camera_turn, config::Range{0.0, 30.0},
          "deg: each episode every such camera's view direction turns by up to this in yaw and in pitch "
          "(uniform); 0 = none");
  v.field("camera_fov", c.camera_fov, config::Range{0.0, 90.0},
          "deg: each episode every such camera's vertical field of view changes by up to this (uniform); 0 = none");
  v.field("colour_noise", c.colour_noise, config::Range{0.0, 1.0},
          "each episode every drawn part's red, green and blue (in [0, 1]) change by up to this (uniform), for "
          "raw-pixel observations; 0 = none");
  v.field("light_turn", c.light_turn, config::Range{0.0, 90.0},
          "deg: each episode the light's direction turns by up to this in yaw and in pitch (uniform), for "
          "raw-pixel observations; 0 = none");
  v.field("observation_noise", c.observation_noise, config::Range{0.0, 1000.0},
          "standard deviation of Gaussian noise added to each observed value at every reset and step, in the "
          "values' own units (metres for positions, so 0.005 is 5 mm); a goal env's desired goal stays exact; "
          "ground-truth observations only; 0 = none");
  v.field("observation_noise_parts", c.observation_noise_parts, config::Range{0.0, 1000.0},
          "{part: standard deviation}: the noise of these parts of the observation instead of observation_noise "
          "(each value of the part gets its own draw), e.g. {\"effector_velocity\": 0.02, \"cube1_position\": 0.005}; "
          "the part names are the env's (Environments: observation parts); 0 = that part exact");
  v.field("action_latency", c.action_latency, config::Range{0, 100000},
          "env steps between an action and the step that executes it (each step runs the action given that "
          "many steps before; the first steps of an episode run its first action); shorter than max_steps; 0 = none");
  v.field("random_latency", c.random_latency,
          "with action_latency: each episode runs with a latency drawn uniformly from 0..action_latency steps (a "
          "policy that cannot know the delay learns to live with any of them)");
  v.field("observe_latency", c.observe_latency,
          "with action_latency: the observation also holds the actions still to run, oldest first (each Box action's "
          "values clipped to its bounds, a Discrete one one-hot), in latency_slots slots (zeros in those not used: "
          "before the episode's first action, or with a shorter latency), after the env's own values and "
          "before a goal env's goals");
  v.field("latency_slots", c.latency_slots, config::Range{0, 100000},
          "observe_latency's slots (at least action_latency); 0 = action_latency. More slots than the latency let "
          "one policy run with any latency up to them, 0 included (an env without latency that keeps the "
          "observation's size)");
  v.check(config::is_range(c.mass_scale), "mass_scale", "expected [lo, hi] with lo <= hi");
  v.check(config::is_range(c.friction_scale), "friction_scale", "expected [lo, hi] with lo <= hi");
  v.check(config::is_range(c.joint_damping), "joint_damping", "expected [lo, hi] with lo <= hi");
  v.check(config::is_range(c.gain_scale), "gain_scale", "expected [lo, hi] with lo <= hi");
}

// The option group robot envs list (their defaults hold it inactive).
struct RandomizeOptions {
  Randomization randomize;
};

template <class V, class C>
  requires config::Describes<C, RandomizeOptions>
void describe(V& v, C& c) {
  v.object("randomize", c.randomize, "domain randomization, drawn from the env's seeded stream (docs: Environments)");
}

// `env` with r's per-step part applied around it (make_env does this), or `env` itself when r has
// none. The config rules (latency shorter than max_steps, noise on ground-truth observations,
// view draws on raw-pixel ones) are read_env_config's (envs/registry.cpp).
std::unique_ptr<Env> randomized(std::unique_ptr<Env> env, const Randomization& r);

}  // namespace rdsim
