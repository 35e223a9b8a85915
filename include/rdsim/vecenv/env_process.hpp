#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/process_owner.hpp"

// A block of a VecEnv's envs stepped in a child process of their own: what lets pixel envs use
// several cores. Mesa's software rasteriser (llvmpipe, behind OSMesa and EGL) draws the frames of
// every GL context of a process one after another (one rasteriser per screen, one screen per
// process, under one mutex), so pixel envs on several threads of one process barely overlap; in
// separate processes they do.
//
// The constructor forks: the child takes over the envs (the parent's copies are destroyed), waits
// for commands, runs them and answers through memory shared with the parent (the step's actions,
// rewards, flags and observations) and a socket pair (the variable-size env states of
// checkpoints). start_*() hands a command over and returns at once, so the caller can step its own
// envs meanwhile; finish() waits for the answer and rethrows an error of the child's as an
// rdsim::Error naming the envs. A child that dies is an rdsim::Error too, never a hang; a parent
// that dies takes its children with it (PR_SET_PDEATHSIG).
//
// Not for envs that hold connections or threads (a RemoteEnv's ZeroMQ socket): fork copies
// memory, not those.
namespace rdsim {

class EnvProcess {
public:
  // Env i of `envs` is env first + i of the VecEnv (for messages). All share `spec`.
  EnvProcess(std::vector<std::unique_ptr<Env>> envs, const Spec& spec, int first);
  ~EnvProcess();  // asks the child to quit and waits for it
  EnvProcess(const EnvProcess&) = delete;
  EnvProcess& operator=(const EnvProcess&) = delete;

  int size() const { return count_; }

  // Resets every env with seeds[i] (nullopt-free: a seed each).
  void start_reset(const std::vector<std::uint64_t>& seeds);
  // Steps each env of the block with its action where it is active (both vectors indexed by the
  // VecEnv's env number: first + i); an env whose episode ends is reset and its final observation kept.
  void start_step(const std::vector<Action>& actions, const std::vector<bool>& active);
  void start_drop_caches();
  // Waits for the command started last; rdsim::Error on the child's error or death.
  void finish();

  // After finish() of a reset or step: env i's current observation, its step's outcome and
  // (when the episode ended) the observation that ended it.
  void copy_observation(int i, ObservationOut out) const;
  StepOutcome outcome(int i) const;
  void copy_final_observation(int i, Observation& out) const;

  // Checkpoints: every env's EnvState::save_state() (empty optional: the env has no EnvState),
  // and load_state() of each (blocking: start_/finish() inside).
  std::vector<std::optional<std::string>> save_states();
  void load_states(const std::vector<std::string>& states, const std::string& source);

private:
  struct Shared;
  void start(std::uint32_t command);
  [[noreturn]] void child_main(std::vector<std::unique_ptr<Env>>& envs);
  void child_run(std::vector<std::unique_ptr<Env>>& envs, std::uint32_t command);
  std::string what_envs() const;
  std::uint8_t* slot(int i) const;
  // An observation stored in a slot at `obs` (values, then bytes) into `out`.
  void copy_from_slot(const std::uint8_t* obs, ObservationOut out) const;

  int count_ = 0, first_ = 0;
  Spec spec_;
  std::size_t obs_bytes_ = 0, value_bytes_ = 0, action_floats_ = 0, slot_bytes_ = 0, map_bytes_ = 0;
  Shared* shared_ = nullptr;  // the control block, followed by one slot per env
  int socket_ = -1;           // the parent's end (the child's end in the child)
  pid_t pid_ = -1;
  bool busy_ = false;         // a command was started and not finished
  ProcessOwner owner_;        // a fork of the parent neither commands nor stops the parent's child
  std::vector<float> scratch_;  // the child's: where its envs write an observation
};

}  // namespace rdsim
