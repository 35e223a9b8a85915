#pragma once
#include <deque>
#include <iosfwd>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"

// Per-episode bookkeeping shared by every algorithm: running return/length per env, one record
// per finished episode (-> episodes.csv) and statistics over the most recent episodes
// (-> progress.csv). Fed by VecEnv::step, so algorithms never call it directly.
namespace rdsim {

struct EpisodeRecord {
  long long episode = 0;      // 1-based, in the order episodes finished
  long long timesteps = 0;    // total env steps (all envs) when it finished
  double episode_return = 0;  // undiscounted sum of rewards
  int length = 0;             // env steps
  bool success = false;       // StepInfo::success on any of its steps
  bool collision = false;     // StepInfo::collision on any of its steps
  bool out_of_bounds = false; // StepInfo::out_of_bounds on any of its steps
  double wall_time = 0;       // seconds of training when it finished
};

// Over the last `window` finished episodes; count == 0 when none has finished yet.
struct EpisodeStats {
  int count = 0;
  double mean_return = 0, min_return = 0, max_return = 0;
  double mean_length = 0;
  double success_rate = 0;
};

class EpisodeTracker {
public:
  explicit EpisodeTracker(int num_envs = 1, int window = 20);

  // One env step of env `env`. When `done`, the episode is recorded and the env's counters restart.
  void on_step(int env, double reward, const StepInfo& info, bool done, long long timesteps, double wall_time);

  // Drops the episodes in progress (their envs were reset without finishing them).
  void forget_running();

  // Records an episode finished elsewhere (another MPI rank's), numbered next: the run's log of
  // several ranks' episodes is a tracker fed only through this.
  void add_finished(EpisodeRecord record);

  // Finished episodes not yet taken, oldest first; taking them empties the list.
  std::vector<EpisodeRecord> take_finished();

  long long episodes() const { return episodes_; }
  int window() const { return window_; }
  EpisodeStats stats() const;
  const std::deque<EpisodeRecord>& recent() const { return recent_; }

  // Everything, including episodes in progress and not-yet-taken records (checkpoints).
  void save(std::ostream& out) const;
  void load(std::istream& in, const std::string& source);

  // Records as bytes (to gather them from MPI ranks); decode throws rdsim::Error naming `source`.
  static std::string encode(const std::vector<EpisodeRecord>& records);
  static std::vector<EpisodeRecord> decode(const std::string& bytes, const std::string& source);

private:
  struct Running {
    double ret = 0;
    int length = 0;
    bool success = false, collision = false, out_of_bounds = false;
  };
  std::vector<Running> running_;
  std::deque<EpisodeRecord> recent_;   // at most window_ records
  std::vector<EpisodeRecord> finished_;
  long long episodes_ = 0;
  int window_;
};

}  // namespace rdsim
