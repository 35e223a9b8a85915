#pragma once
#include <cstdint>
#include <string>

// `rdsim demos info FILE` and `rdsim demos record --expert ...` (src/app/demos.cpp): demonstration
// files (rdsim/demos/demo_file.hpp) and the scripted expert (rdsim/envs/reaching/reach_expert.hpp).
namespace rdsim {

// Prints the file's env, spaces, episodes, steps, success rate and mean return.
int demos_info_command(const std::string& path);

struct DemosRecordOptions {
  bool expert = false;         // --expert: optional, the scripted expert is this command's only recorder
  std::string env;             // registry name: its default options, random targets (see below)
  std::string config_path;     // or the "env" object of this training config, as it is
  int episodes = 20;           // episodes written
  std::string out_path;
  std::uint64_t seed = 1000;   // episode k (0-based) starts from reset(seed + k)
  bool append = false;         // add to an existing file (of the same env)
  bool fixed_target = false;   // --env: keep the env's default target (random_target false)
  bool continuous = false;     // --env: Box(3) actions (is_discrete false)
  bool only_successes = false; // write successful episodes only (trying at most 10x episodes)
  // Box actions: standard deviation, in action units, of the Gaussian noise added to each of the
  // expert's actions before it is taken (then clipped to the space). The file holds the actions
  // taken. The episodes visit states off the expert's own path together with its way back, which a
  // policy cloned from them needs (DART, Laskey et al. 2017); 0 = the expert's actions as they are.
  double action_noise = 0.0;
  // pick_and_place, stack: the share of episodes (drawn from each episode's seed) whose first grasp
  // goes down 4.5-6 cm beside the first cube along x (across the fingers), on a side drawn the
  // same way, and closes on
  // nothing before the expert goes back up and grasps it (ManipulationExpert::miss_first_grasp):
  // episodes that show the way back from a missed grasp. 0 = none.
  double missed_grasps = 0.0;
  bool quiet = false;
};
// Runs the scripted expert and appends each episode, labelled "scripted", as it ends.
int demos_record_command(const DemosRecordOptions& options);

}  // namespace rdsim
