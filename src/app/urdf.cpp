// `rdsim urdf FILE`: a robot's links and joints, the links that could be its effector, and a reach
// config skeleton for it.
#include "rdsim/app/urdf.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "rdsim/app/command.hpp"
#include "rdsim/core/config_path.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim {
namespace {

const char* type_name(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Continuous: return "continuous";
    case JointType::Prismatic: return "prismatic";
    case JointType::Fixed: return "fixed";
  }
  return "?";
}

// The movable joints from the root down to `link`, root first.
std::vector<int> movable_chain(const RobotModel& m, int link) {
  std::vector<int> chain;
  for (int l = link; l > 0; l = m.joints[static_cast<size_t>(m.links[static_cast<size_t>(l)].parent_joint)].parent_link) {
    const int j = m.links[static_cast<size_t>(l)].parent_joint;
    if (m.joints[static_cast<size_t>(j)].movable()) chain.push_back(j);
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

// Effector candidates: the links with no child link, below at least one movable joint; first those
// whose chain has the fewest prismatic joints (a finger's slide is a gripper's, not the arm's), then
// the most movable joints.
std::vector<int> effector_candidates(const RobotModel& m) {
  std::vector<bool> has_child(m.links.size(), false);
  for (const Joint& j : m.joints) has_child[static_cast<size_t>(j.parent_link)] = true;
  std::vector<int> leaves;
  for (int l = 1; l < static_cast<int>(m.links.size()); ++l)
    if (!has_child[static_cast<size_t>(l)] && !movable_chain(m, l).empty()) leaves.push_back(l);
  const auto prismatic = [&](int l) {
    const std::vector<int> chain = movable_chain(m, l);
    return std::count_if(chain.begin(), chain.end(), [&](int j) { return m.joints[static_cast<size_t>(j)].type == JointType::Prismatic; });
  };
  std::stable_sort(leaves.begin(), leaves.end(), [&](int a, int b) {
    if (prismatic(a) != prismatic(b)) return prismatic(a) < prismatic(b);
    return movable_chain(m, a).size() > movable_chain(m, b).size();
  });
  return leaves;
}

std::string limits_text(const Joint& j) {
  const char* unit = j.type == JointType::Prismatic ? "m" : "rad";
  char buf[160];
  if (j.type == JointType::Continuous)
    std::snprintf(buf, sizeof buf, "unlimited, effort %g, velocity %g %s/s", j.effort, j.velocity, unit);
  else
    std::snprintf(buf, sizeof buf, "[%g, %g] %s, effort %g, velocity %g %s/s", j.lower, j.upper, unit, j.effort, j.velocity, unit);
  return buf;
}

// A reach config for the chain down to `effector`: every movable joint of it at 0 (or the middle
// of its range when 0 is outside it); a workspace box of the arm's reach r (the effector's distance
// from the root with every joint at 0, an arm stretched out) around its base, targets in front.

nlohmann::ordered_json skeleton(const RobotModel& m, const UrdfOptions& o, int effector) {
  nlohmann::ordered_json joints = nlohmann::ordered_json::array(), home = nlohmann::ordered_json::array();
  for (int j : movable_chain(m, effector)) {
    const Joint& joint = m.joints[static_cast<size_t>(j)];
    joints.push_back(joint.name);
    const bool zero_inside = joint.type == JointType::Continuous || (joint.lower <= 0.0 && 0.0 <= joint.upper);
    home.push_back(zero_inside ? 0.0 : std::round((joint.lower + joint.upper) / 2.0 * 1e4) / 1e4);
  }
  nlohmann::ordered_json env = {{"name", "reach"}, {"urdf", path_from("", o.path)}};
  if (!o.package_paths.empty()) {
    nlohmann::ordered_json paths = nlohmann::ordered_json::array();
    for (const auto& p : o.package_paths) paths.push_back(path_from("", p));
    env["package_paths"] = paths;
  }
  env["effector_link"] = m.links[static_cast<size_t>(effector)].name;
  env["joints"] = joints;
  env["home_pose"] = home;
  const double r = std::max(0.1, std::ceil(m.link_poses_at_zero()[static_cast<size_t>(effector)].translation().norm() / 0.05) * 0.05);
  const auto cm = [](double v) { return std::round(v * 100.0) / 100.0; };  // m, to the centimetre
  env["workspace_min"] = {cm(-r), cm(-r), 0.02};
  env["workspace_max"] = {cm(r), cm(r), cm(r)};
  env["target_centre"] = {cm(r / 2), 0.0, cm(r / 2)};
  env["target_half_range"] = {cm(r / 4), cm(r / 4), cm(r / 4)};
  nlohmann::ordered_json config;
  config["algorithm"] = "ppo";
  config["env"] = env;
  config["total_timesteps"] = 300000;
  return config;
}

}  // namespace

int urdf_command(const UrdfOptions& o) {
  UrdfLoadOptions load;
  load.search_path = o.package_paths;
  const RobotModel m = load_urdf(o.path, load);  // rdsim::Error naming the file
  std::printf("robot %s (%s): %zu links, %zu joints (%d movable), %.3g kg\n", m.name.c_str(), o.path.c_str(), m.links.size(),
              m.joints.size(), m.movable_joint_count(), m.total_mass());
  std::printf("\njoints, root first (parent link -> child link):\n");
  for (const Joint& j : m.joints)
    std::printf("  %-28s %-10s %s -> %s%s%s\n", j.name.c_str(), type_name(j.type),
                m.links[static_cast<size_t>(j.parent_link)].name.c_str(), m.links[static_cast<size_t>(j.child_link)].name.c_str(),
                j.movable() ? "  " : "", j.movable() ? limits_text(j).c_str() : "");
  const std::vector<int> candidates = effector_candidates(m);
  if (candidates.empty()) {
    std::printf("\nno link below a movable joint: nothing to move (a reach env needs an arm)\n");
    return 0;
  }
  std::printf("\neffector candidates (links at the end of a chain; movable joints above them):\n");
  for (int l : candidates)
    std::printf("  %-28s %zu\n", m.links[static_cast<size_t>(l)].name.c_str(), movable_chain(m, l).size());
  std::printf("\na reach config for %s (check home_pose, then set workspace_min/max and target_centre/half_range "
              "for your robot: `rdsim config-reference`; `rdsim render --config FILE` draws it):\n%s\n",
              m.links[static_cast<size_t>(candidates.front())].name.c_str(), skeleton(m, o, candidates.front()).dump(2).c_str());
  return 0;
}

Command urdf_command_entry() {
  return {"urdf", "Print a URDF's links and joints (types, limits), its effector candidates and a reach config for it",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<UrdfOptions>();
            cmd.add_option("file", o->path, "The URDF file")->required();
            cmd.add_option("--package-path", o->package_paths, "Folder for package:// meshes (repeatable; env.package_paths)");
            return [o] { return urdf_command(*o); };
          }};
}

}  // namespace rdsim
