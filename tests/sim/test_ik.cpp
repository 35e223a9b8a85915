#include <catch2/catch.hpp>

#include <cmath>

#include "rdsim/core/rng.hpp"
#include "rdsim/sim/ik.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

JointVector random_config(const KinematicChain& chain, Rng& rng) {
  JointVector q(chain.dof());
  for (int i = 0; i < chain.dof(); ++i)
    q[i] = rng.uniform(std::max(chain.lower()[i], -M_PI), std::min(chain.upper()[i], M_PI));
  return q;
}

bool within_limits(const KinematicChain& chain, const JointVector& q) {
  return (q.array() >= chain.lower().array()).all() && (q.array() <= chain.upper().array()).all();
}

}  // namespace

TEST_CASE("IK reaches 50 random reachable positions within 2 mm", "[ik]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  Rng rng(2024);
  IkOptions options;
  options.max_iterations = 300;
  options.restarts = 10;
  int reached = 0;
  for (int t = 0; t < 50; ++t) {
    const Eigen::Vector3d target = chain.forward(random_config(chain, rng)).translation();
    const JointVector start = random_config(chain, rng);
    const IkResult r = solve_ik(chain, target, start, options);
    const double error = (chain.forward(r.q).translation() - target).norm();
    INFO("target " << target.transpose() << " error " << error << " after " << r.iterations << " iterations");
    CHECK(error < 2e-3);
    CHECK(r.position_error == Approx(error).margin(1e-12));
    CHECK(within_limits(chain, r.q));
    reached += error < 2e-3;
  }
  CHECK(reached == 50);
}

TEST_CASE("Pose IK reaches position and orientation", "[ik]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  Rng rng(5);
  for (int t = 0; t < 20; ++t) {
    const JointVector truth = random_config(chain, rng);
    JointVector start = truth;
    for (int i = 0; i < 6; ++i) start[i] += rng.uniform(-0.3, 0.3);
    const Eigen::Isometry3d target = chain.forward(truth);
    const IkResult r = solve_ik(chain, target, start);
    const Eigen::Isometry3d got = chain.forward(r.q);
    CHECK(r.converged);
    CHECK((got.translation() - target.translation()).norm() < 1e-3);
    CHECK(Eigen::AngleAxisd(got.linear() * target.linear().transpose()).angle() < 1e-2);
  }
}

TEST_CASE("IK from the current pose to a 1 cm move takes a few iterations", "[ik]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  JointVector q(6);
  q << 0.0, 1.0, -1.8, 0.8, 1.5, 0.0;
  Eigen::Isometry3d target = chain.forward(q);
  target.translation() += Eigen::Vector3d(0.01, 0.0, 0.0);
  const IkResult r = solve_ik(chain, target, q);
  CHECK(r.converged);
  CHECK(r.iterations <= 4);
}

TEST_CASE("Unreachable targets end inside the joint limits, not converged", "[ik]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  const IkResult r = solve_ik(chain, Eigen::Vector3d(2.0, 0.0, 0.5), JointVector::Zero(6));
  CHECK_FALSE(r.converged);
  CHECK(r.position_error > 1.0);
  CHECK(within_limits(chain, r.q));
}

TEST_CASE("null-space IK (pybullet-style): 20 iterations close most of a 10 cm move, limits push back", "[ik]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  JointVector q(6), rest(6);
  q << 0.0, 1.0, -1.8, 0.8, 1.5, 0.0;
  rest << 0.0, 0.0, 1.0, 1.0, 1.0, 1.0;
  const Eigen::Vector3d tip = chain.forward(q).translation();

  // A reachable goal 10 cm away: damping 0.6 m makes each step short, 20 of them get close.
  const Eigen::Vector3d near = tip + Eigen::Vector3d(0.1, 0.0, 0.0);
  const JointVector solved = null_space_ik(chain, near, q, rest);
  CHECK((chain.forward(solved).translation() - near).norm() < 0.01);
  CHECK(within_limits(chain, solved));

  // The goal where the tip already is: as pybullet, one step is still taken, and the rest pull
  // (0.001 x (rest - q)) moves the joints by under 3 mrad; the damped projection lets part of it
  // reach the tip (under 1 mm; pybullet's does the same).
  const JointVector still = null_space_ik(chain, tip, q, rest);
  CHECK((still - q).cwiseAbs().maxCoeff() < 3e-3);
  CHECK((chain.forward(still).translation() - tip).norm() < 1e-3);

  // RobotDrlSim's far targets (1 m along one axis): the tip heads that way, and no iteration moves
  // a joint by more than 45 degrees.
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d far = tip;
    far[axis] += 1.0;
    NullSpaceIkOptions one_step;
    one_step.iterations = 1;
    const JointVector first = null_space_ik(chain, far, q, rest, one_step);
    CHECK((first - q).cwiseAbs().maxCoeff() <= M_PI / 4.0 + 1e-12);
    const JointVector r = null_space_ik(chain, far, q, rest);
    CHECK(chain.forward(r).translation()[axis] > tip[axis] + 0.05);
  }

  // A joint beyond its limit is pushed back (10 x overshoot / range per iteration), not clamped.
  JointVector beyond = q;
  beyond[1] = chain.upper()[1] + 0.2;
  NullSpaceIkOptions one_step;
  one_step.iterations = 1;
  const JointVector pushed = null_space_ik(chain, chain.forward(beyond).translation(), beyond, rest, one_step);
  CHECK(pushed[1] < beyond[1] - 0.05);
}
