#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/rng.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/randomization.hpp"

// The per-episode part of a Randomization (randomization.hpp) for the envs built on a ReachTask
// (the reaching and manipulation tasks). At each reset it draws, from its own stream
// (rng_stream::episode_randomization of the reset seed), in this order: one mass factor per robot
// link, then per object; one friction factor for the robot, then one per object; a damping per
// robot joint; the drive's position and velocity gain factors; the env's placement offsets (x, y
// in +-placement_noise); per pixel camera a shift, a yaw, a pitch and a field-of-view change; the
// light's yaw and pitch; the colours' seed. The physical draws are applied to the task at once (on
// top of the values it had when the randomizer was made: build it after the env set its own
// frictions); the env applies the placements and gives the view draws to its PixelView. The
// objects are the task's free bodies. Without per-episode randomization it does nothing.
namespace rdsim {

class ReachTask;

class TaskRandomizer {
public:
  // `placements`: the offsets the env takes each episode (its target and objects).
  TaskRandomizer(ReachTask& task, const Randomization& r, int placements);

  bool active() const { return r_.per_episode(); }
  // A new episode: the stream reseeded when `seed` is given, then the draws, applied to the task.
  void reset(std::optional<std::uint64_t> seed);
  // m, world frame: placement offset k (in 0..placements) of this episode; zero when inactive.
  Eigen::Vector3f placement(int k) const;
  // This episode's camera, colour and light draws for `view`.
  void apply(PixelView& view) const;

  // For the env's saved state (only when active): the stream as this episode's draws began. load()
  // draws again from it and applies the physical draws. rdsim::Error naming `source` on bad bytes.
  void save(std::ostream& out) const;
  void load(std::istream& in, const std::string& source);

private:
  struct Nominal {
    std::vector<int> objects;                           // PhysicsWorld body ids of the free bodies
    std::vector<float> object_friction, joint_damping;  // as the task had them
    float position_gain = 1.0f, velocity_gain = 1.0f;
  };
  struct Draw {
    std::vector<double> link_mass, object_mass;
    float robot_friction = 1.0f;
    std::vector<float> object_friction, joint_damping;
    float position_gain = 1.0f, velocity_gain = 1.0f;
    std::vector<Eigen::Vector3f> placements;
    ViewVariation view;
  };

  void draw();            // from episode_start_ into draw_ (rng_ ends past the draws)
  void apply_physics();

  ReachTask& task_;
  Randomization r_;
  int placements_;
  Nominal nominal_;
  Rng episode_start_ = Rng::derive(0, rng_stream::episode_randomization);
  Rng rng_ = episode_start_;
  Draw draw_;
};

}  // namespace rdsim
