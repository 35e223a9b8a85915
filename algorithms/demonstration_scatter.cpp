#include "rdsim/algorithms/demonstration_scatter.hpp"

#include <algorithm>
#include <limits>

#include "rdsim/core/assert.hpp"
#include "rdsim/demos/demo_file.hpp"

namespace rdsim {
namespace {

constexpr float kUnmoved = 1e-3f;  // m: a resting object settles by less (the envs' own rule)
constexpr float kSettled = 0.01f;  // m from where it ends: an object put down (what is stacked on it later nudges it less)
constexpr float kApart = 0.06f;    // m in x, y between objects, and from a goal: the reset's 1.5 cube sizes
constexpr float kClear = 0.10f;    // m in x, y from the effector: clear of the open fingers
constexpr int kTries = 20;         // draws of a new place before the object or goal stays

Eigen::Vector2f xy(const Eigen::MatrixXf& m, int row, int column) { return {m(row, column), m(row + 1, column)}; }

void move_xy(Eigen::MatrixXf& m, int row, int column, const Eigen::Vector2f& by) {
  m(row, column) += by.x();
  m(row + 1, column) += by.y();
}

Eigen::Vector2f draw_in(const Eigen::Vector2f& low, const Eigen::Vector2f& high, Rng& rng) {
  return {static_cast<float>(rng.uniform(low.x(), high.x())), static_cast<float>(rng.uniform(low.y(), high.y()))};
}

}  // namespace

bool DemonstrationScatter::supported(const Spec& spec) {
  if (!spec.goal.active() || spec.observation.type != ObsType::Float32) return false;
  const auto objects = std::count_if(spec.observation.parts.begin(), spec.observation.parts.end(), [](const ObservationPart& p) {
    return p.size == 3 && p.name.ends_with("_position") && p.name != "effector_position";
  });
  return objects > 0 && objects < 8;  // an idle mask holds seven objects and the goal
}

DemonstrationScatter::DemonstrationScatter(const DemoFile& demos, const Spec& spec, bool goal)
    : goal_(spec.goal), goal_scatter_(goal) {
  RDSIM_ASSERT(supported(spec) && !demos.episodes.empty(), "demonstrations.scatter is checked before the buffer is built");
  const ObservationSpace& space = spec.observation;
  effector_ = space.part("effector_position").first;
  int at = 0;
  for (const ObservationPart& p : space.parts) {
    if (p.size == 3 && p.name.ends_with("_position") && p.name != "effector_position") {
      Object o;
      o.position = at;
      const auto [from, size] = space.part(p.name.substr(0, p.name.size() - 9) + "_from_effector");
      if (size == 3) o.from_effector = from;
      objects_.push_back(o);
    }
    at += p.size;
  }
  RDSIM_ASSERT(objects_.size() < 8, "an idle mask holds seven objects and the goal");
  // Which achieved-goal point is which object: the one it equals in the first demonstrated state.
  const Eigen::VectorXf& first = demos.episodes.front().observations.front().values;
  for (Object& o : objects_)
    for (int p = 0; p < goal_.points; ++p)
      if ((first.segment<3>(o.position) - first.segment<3>(goal_.achieved_offset() + 3 * p)).norm() < 1e-5f) o.goal_point = p;

  const float inf = std::numeric_limits<float>::infinity();
  object_low_ = goal_low_ = Eigen::Vector2f::Constant(inf);
  object_high_ = goal_high_ = Eigen::Vector2f::Constant(-inf);
  for (const DemoEpisode& e : demos.episodes) {
    const Eigen::VectorXf& start = e.observations.front().values;
    const int steps = e.steps();
    std::vector<int> moved_at, settled_at;  // per object: the first observation in which it has moved
                                            // (steps + 1: never), and the first from which it stays put
    for (const Object& o : objects_) {
      const auto at = [&](int t) -> Eigen::Vector3f { return e.observations[static_cast<std::size_t>(t)].values.segment<3>(o.position); };
      int t = 0;
      while (t <= steps && (at(t) - at(0)).norm() <= kUnmoved) ++t;
      moved_at.push_back(t);
      int s = steps;
      while (s > 0 && (at(s - 1) - at(steps)).norm() <= kSettled) --s;
      settled_at.push_back(s);
      object_low_ = object_low_.cwiseMin(at(0).head<2>());
      object_high_ = object_high_.cwiseMax(at(0).head<2>());
    }
    // Object k is idle until the demonstrator can be going for it: until every object moved
    // before it is put down (the first one moved is never idle).
    std::vector<int> idle_until(objects_.size(), 0);
    for (std::size_t k = 0; k < objects_.size(); ++k)
      for (std::size_t j = 0; j < objects_.size(); ++j)
        if (moved_at[j] < moved_at[k]) idle_until[k] = std::max(idle_until[k], std::min(settled_at[j], moved_at[k]));
    const Eigen::Vector2f goal0 = start.segment<2>(goal_.desired_offset());
    goal_low_ = goal_low_.cwiseMin(goal0);
    goal_high_ = goal_high_.cwiseMax(goal0);
    for (int t = 0; t < steps; ++t) {
      // The transition t -> t + 1: idle objects stay unmoved through it, before their time.
      std::uint8_t mask = 0;
      bool none_moved = true;
      for (std::size_t k = 0; k < objects_.size(); ++k) {
        none_moved = none_moved && moved_at[k] > t + 1;
        if (t + 1 < idle_until[k]) mask |= static_cast<std::uint8_t>(1u << k);
      }
      if (none_moved && goal_scatter_) mask |= kGoalBit;
      idle_.push_back(mask);
    }
  }
}

bool DemonstrationScatter::clear_of_objects(const Eigen::Vector2f& at, int self, const ReplayBatch& out, int column) const {
  for (const Eigen::MatrixXf* m : {&out.observations, &out.next_observations}) {
    if (effector_ >= 0 && self >= 0 && (at - xy(*m, effector_, column)).norm() < kClear) return false;
    for (int k = 0; k < objects(); ++k)
      if (k != self && (at - xy(*m, objects_[static_cast<std::size_t>(k)].position, column)).norm() < kApart) return false;
  }
  return true;
}

// Every desired point not met by an idle object moves by one offset that puts the first of them in
// the demonstrations' goal rectangle, clear of the objects (none has moved yet).
bool DemonstrationScatter::scatter_goal(const std::vector<bool>& tied, int column, Rng& rng, ReplayBatch& out) const {
  const int desired = goal_.desired_offset();
  int lead = 0;
  while (lead < goal_.points && tied[static_cast<std::size_t>(lead)]) ++lead;
  if (lead == goal_.points) return false;
  for (int t = 0; t < kTries; ++t) {
    const Eigen::Vector2f by = draw_in(goal_low_, goal_high_, rng) - xy(out.observations, desired + 3 * lead, column);
    bool clear = true;
    for (int p = 0; p < goal_.points && clear; ++p)
      if (!tied[static_cast<std::size_t>(p)])
        clear = clear_of_objects(xy(out.observations, desired + 3 * p, column) + by, -1, out, column);
    if (!clear) continue;
    for (int p = 0; p < goal_.points; ++p) {
      if (tied[static_cast<std::size_t>(p)]) continue;
      move_xy(out.observations, desired + 3 * p, column, by);
      move_xy(out.next_observations, desired + 3 * p, column, by);
    }
    return true;
  }
  return false;
}

// Idle object k to a new place in the demonstrations' object rectangle, clear of the effector, the
// other objects and the desired points it does not meet; what it carries (its position from the
// effector, its achieved point, a desired point it meets) moves with it.
bool DemonstrationScatter::scatter_object(int k, const std::vector<bool>& tied, int column, Rng& rng, ReplayBatch& out) const {
  const Object& o = objects_[static_cast<std::size_t>(k)];
  const int desired = goal_.desired_offset();
  for (int t = 0; t < kTries; ++t) {
    const Eigen::Vector2f at = draw_in(object_low_, object_high_, rng);
    bool clear = clear_of_objects(at, k, out, column);
    for (int p = 0; p < goal_.points && clear; ++p)
      if (!(p == o.goal_point && tied[static_cast<std::size_t>(p)]))
        clear = (at - xy(out.observations, desired + 3 * p, column)).norm() >= kApart;
    if (!clear) continue;
    const Eigen::Vector2f by = at - xy(out.observations, o.position, column);
    for (Eigen::MatrixXf* m : {&out.observations, &out.next_observations}) {
      move_xy(*m, o.position, column, by);
      if (o.from_effector >= 0) move_xy(*m, o.from_effector, column, by);
      if (o.goal_point >= 0) {
        move_xy(*m, goal_.achieved_offset() + 3 * o.goal_point, column, by);
        if (tied[static_cast<std::size_t>(o.goal_point)]) move_xy(*m, desired + 3 * o.goal_point, column, by);
      }
    }
    return true;
  }
  return false;
}

void DemonstrationScatter::apply(long long slot, int column, Rng& rng, ReplayBatch& out) const {
  const std::uint8_t mask = idle(slot);
  if (mask == 0) return;
  const int achieved = goal_.achieved_offset(), desired = goal_.desired_offset();
  const auto next_goals = [&] {
    return std::pair{out.next_observations.col(column).data() + achieved, out.next_observations.col(column).data() + desired};
  };
  const bool was_success = goal_.is_success(next_goals().first, next_goals().second);
  // A desired point that an idle object meets where it lies (a hindsight goal) is that object's.
  std::vector<bool> tied(static_cast<std::size_t>(goal_.points), false);
  for (int k = 0; k < objects(); ++k) {
    const Object& o = objects_[static_cast<std::size_t>(k)];
    if ((mask >> k & 1u) && o.goal_point >= 0)
      tied[static_cast<std::size_t>(o.goal_point)] =
          (out.observations.col(column).segment<3>(o.position) - out.observations.col(column).segment<3>(desired + 3 * o.goal_point)).norm() <
          goal_.distance_threshold;
  }
  bool changed = (mask & kGoalBit) && scatter_goal(tied, column, rng, out);
  for (int k = 0; k < objects(); ++k)
    if (mask >> k & 1u) changed = scatter_object(k, tied, column, rng, out) || changed;
  if (!changed) return;
  const auto [a, d] = next_goals();
  const bool success = goal_.is_success(a, d);
  out.rewards[column] = goal_.reward_of(a, d);
  // The goal envs end an episode at its goal; any other end (none in these tasks) stays.
  out.terminated[column] = success || (out.terminated[column] > 0.5f && !was_success) ? 1.0f : 0.0f;
}

}  // namespace rdsim
