#include "rdsim/envs/reaching/reach_expert.hpp"

#include <algorithm>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

ReachEnv& reach_env(Env& env) {
  auto* reach = dynamic_cast<ReachEnv*>(&env);
  if (!reach)
    throw Error("env " + env.spec().env_name + " has no scripted expert (the reaching envs jaka_button, "
                "jaka_obstacle and inmoov_tomato have one)");
  return *reach;
}

}  // namespace

ReachExpert::ReachExpert(Env& env) : env_(reach_env(env)) {}

void ReachExpert::reset() { next_point_ = 0; }

std::size_t ReachExpert::points() const {
  return env_.terms().expert_route.size() + (env_.terms().expert_approach.isZero() ? 0 : 1);
}

Eigen::Vector3f ReachExpert::aim() const {
  const ReachTerms& terms = env_.terms();
  const Eigen::Vector3f& target = env_.task().target();
  if (next_point_ < terms.expert_route.size()) return terms.expert_route[next_point_];
  if (next_point_ < points()) return target + terms.expert_approach;
  return target;
}

Action ReachExpert::act() {
  const Eigen::Vector3f& ee = env_.task().ee_position();
  while (next_point_ < points() && (aim() - ee).norm() < route_tolerance) ++next_point_;
  const Eigen::Vector3f error = aim() - ee;
  if (env_.spec().action.discrete) {
    Eigen::Index axis;
    error.cwiseAbs().maxCoeff(&axis);
    return Action::discrete(2 * static_cast<int>(axis) + (error[axis] > 0.0f ? 1 : 0));
  }
  // Along the remaining vector, full speed on its longest axis (clipping each axis alone would bend the path).
  const float scale = std::max(env_.task().spec().step, error.cwiseAbs().maxCoeff());
  return Action::continuous((error / scale).cwiseMax(-1.0f).cwiseMin(1.0f).eval());
}

}  // namespace rdsim
