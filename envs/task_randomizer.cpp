#include "rdsim/envs/task_randomizer.hpp"

#include <cmath>
#include <istream>
#include <ostream>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"

namespace rdsim {
namespace {

constexpr int kCameras = 2;  // view draws are made for two cameras whatever the env has (a fixed draw order)
constexpr double kDegree = M_PI / 180.0;

double in_range(Rng& rng, const std::vector<double>& range) { return rng.uniform(range[0], range[1]); }

// A value in [-amplitude, amplitude].
float spread(Rng& rng, double amplitude) { return static_cast<float>(rng.uniform(-amplitude, amplitude)); }

}  // namespace

TaskRandomizer::TaskRandomizer(ReachTask& task, const Randomization& r, int placements)
    : task_(task), r_(r), placements_(placements) {
  const PhysicsWorld& world = task.world();
  for (size_t i = 0; i < task.spec().statics.size(); ++i) {
    const int body = task.static_body(static_cast<int>(i));
    if (!world.is_free_body(body)) continue;
    nominal_.objects.push_back(body);
    nominal_.object_friction.push_back(world.free_body_friction(body));
  }
  const Robot& robot = task.robot();
  for (int d = 0; d < robot.dof(); ++d) nominal_.joint_damping.push_back(robot.joint_damping(d));
  nominal_.position_gain = robot.position_gain();
  nominal_.velocity_gain = robot.velocity_gain();
}

void TaskRandomizer::reset(std::optional<std::uint64_t> seed) {
  if (!active()) return;
  if (seed) rng_ = Rng::derive(*seed, rng_stream::episode_randomization);
  episode_start_ = rng_;
  draw();
  apply_physics();
}

void TaskRandomizer::draw() {
  Rng& rng = rng_ = episode_start_;
  Draw d;
  const size_t links = task_.robot_model().links.size(), objects = nominal_.objects.size();
  for (size_t l = 0; l < links; ++l) d.link_mass.push_back(in_range(rng, r_.mass_scale));
  for (size_t o = 0; o < objects; ++o) d.object_mass.push_back(in_range(rng, r_.mass_scale));
  d.robot_friction = static_cast<float>(in_range(rng, r_.friction_scale));
  for (size_t o = 0; o < objects; ++o)
    d.object_friction.push_back(nominal_.object_friction[o] * static_cast<float>(in_range(rng, r_.friction_scale)));
  for (float nominal : nominal_.joint_damping) d.joint_damping.push_back(nominal + static_cast<float>(in_range(rng, r_.joint_damping)));
  d.position_gain = nominal_.position_gain * static_cast<float>(in_range(rng, r_.gain_scale));
  d.velocity_gain = nominal_.velocity_gain * static_cast<float>(in_range(rng, r_.gain_scale));
  for (int k = 0; k < placements_; ++k) {
    const float x = spread(rng, r_.placement_noise);  // two statements: argument order is unspecified
    const float y = spread(rng, r_.placement_noise);
    d.placements.emplace_back(x, y, 0.0f);
  }
  for (int c = 0; c < kCameras; ++c) {
    ViewVariation::CameraChange change;
    for (int i = 0; i < 3; ++i) change.shift[i] = spread(rng, r_.camera_shift);
    change.yaw = spread(rng, r_.camera_turn * kDegree);
    change.pitch = spread(rng, r_.camera_turn * kDegree);
    change.fov = spread(rng, r_.camera_fov);
    d.view.cameras.push_back(change);
  }
  d.view.light_yaw = spread(rng, r_.light_turn * kDegree);
  d.view.light_pitch = spread(rng, r_.light_turn * kDegree);
  d.view.colour_noise = static_cast<float>(r_.colour_noise);
  d.view.colour_seed = rng.next_u64();
  draw_ = std::move(d);
}

void TaskRandomizer::apply_physics() {
  Robot& robot = task_.robot();
  PhysicsWorld& world = task_.world();
  robot.set_mass_scales(draw_.link_mass);
  robot.set_friction_scale(draw_.robot_friction);
  for (int d = 0; d < robot.dof(); ++d) robot.set_joint_damping(d, draw_.joint_damping[static_cast<size_t>(d)]);
  robot.set_gains(draw_.position_gain, draw_.velocity_gain);
  for (size_t o = 0; o < nominal_.objects.size(); ++o) {
    world.set_free_body_mass_scale(nominal_.objects[o], draw_.object_mass[o]);
    // Only a change: setting a friction also gives the body friction anchors (PhysicsWorld).
    if (world.free_body_friction(nominal_.objects[o]) != draw_.object_friction[o])
      world.set_free_body_friction(nominal_.objects[o], draw_.object_friction[o]);
  }
}

Eigen::Vector3f TaskRandomizer::placement(int k) const {
  RDSIM_ASSERT(k >= 0 && k < placements_, "a placement the env declared");
  return active() ? draw_.placements[static_cast<size_t>(k)] : Eigen::Vector3f::Zero();
}

void TaskRandomizer::apply(PixelView& view) const {
  if (active() && r_.varies_view()) view.vary(draw_.view);
}

void TaskRandomizer::save(std::ostream& out) const { write_string(out, rng_to_bytes(episode_start_)); }

void TaskRandomizer::load(std::istream& in, const std::string& source) {
  episode_start_ = rng_from_bytes(read_string(in, source), source);
  draw();
  apply_physics();
}

}  // namespace rdsim
