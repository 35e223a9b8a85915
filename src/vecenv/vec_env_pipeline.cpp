// VecEnv's pipelined groups (send / recv): while the caller acts on one group of envs, the pool's
// workers step the groups already sent. Why: with step(), every batch step ends at a barrier
// where a worker whose envs are done waits for the other's last env step (about half a step on
// average); with groups in flight a worker goes straight on to the next group's envs.
//
// Who does what: the workers (1..T-1) run one long pool job (start_pipeline to stop_pipeline)
// that claims env steps from the groups in flight, in turn; the caller claims them too
// while it waits in recv(). Each env of a sent group is claimed exactly once (an atomic index per
// worker's part of the group), and a group is re-sent only after it was received, so an env is
// never stepped twice at once. Everything shared (timesteps, episode tracker) is updated by recv()
// on the calling thread, in env order.
#include <utility>

#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/vec_env.hpp"

namespace rdsim {

void VecEnv::set_groups(int groups) {
  require_idle("set_groups");
  if (groups < 1 || groups > size())
    throw Error("VecEnv::set_groups: expected 1.." + std::to_string(size()) + " groups (one env at least in each), got " +
                std::to_string(groups));
  groups_ = groups;
  group_active_.assign(static_cast<std::size_t>(groups), std::vector<bool>(envs_.size(), false));
  for (int g = 0; g < groups; ++g)
    for (int i = group_first(g); i < group_end(g); ++i) group_active_[static_cast<std::size_t>(g)][static_cast<std::size_t>(i)] = true;
  sent_actions_.assign(envs_.size(), Action{});
  env_errors_.assign(envs_.size(), nullptr);
  group_done_ = std::make_unique<GroupProgress[]>(static_cast<std::size_t>(groups * pool_.size()));
  group_expected_.assign(static_cast<std::size_t>(groups), 0);
  group_overlaps_.assign(static_cast<std::size_t>(groups), false);
  group_next_ = std::make_unique<NextEnv[]>(static_cast<std::size_t>(groups * pool_.size()));
  // Every part starts exhausted: nothing to claim before the first send.
  for (int g = 0; g < groups; ++g)
    for (int w = 0; w < pool_.size(); ++w) group_next_[static_cast<std::size_t>(g * pool_.size() + w)].index.store(group_end(g));
  next_send_ = next_recv_ = in_flight_ = 0;
}

void VecEnv::require_idle(const char* what) const {
  if (in_flight_ > 0)
    throw Error(std::string("VecEnv::") + what + ": " + std::to_string(in_flight_) +
                " group(s) sent and not received; recv() them first");
}

void VecEnv::send(int group, const std::vector<Action>& actions) {
  if (actions.size() != envs_.size()) throw Error("VecEnv::send: one action per env expected");
  if (group != next_send_ || in_flight_ == groups_)
    throw Error("VecEnv::send: group " + std::to_string(group) + " sent out of turn (next: " + std::to_string(next_send_) +
                ", " + std::to_string(in_flight_) + " of " + std::to_string(groups_) + " in flight)");
  const int first = group_first(group), end = group_end(group), workers = pool_.size();
  for (int i = first; i < end; ++i) sent_actions_[static_cast<std::size_t>(i)] = actions[static_cast<std::size_t>(i)];
  next_send_ = (group + 1) % groups_;
  ++in_flight_;
  // Decided once per send, for its recv: whether the workers step the group or recv() does.
  group_overlaps_[static_cast<std::size_t>(group)] = overlaps();
  if (!group_overlaps_[static_cast<std::size_t>(group)]) return;
  group_expected_[static_cast<std::size_t>(group)] += end - first;
  // Release: a worker that claims an index (acq_rel) sees the actions.
  for (int w = 0; w < workers; ++w)
    group_next_[static_cast<std::size_t>(group * workers + w)].index.store(first + w * (end - first) / workers,
                                                                           std::memory_order_release);
  posts_.fetch_add(1);
  posts_.notify_all();
  if (!pipeline_running_) start_pipeline();
}

int VecEnv::step_one_sent(int w, int first_group) {
  const int workers = pool_.size();
  for (int k = 0; k < groups_; ++k) {
    const int g = (first_group + k) % groups_, first = group_first(g), n = group_end(g) - first;
    for (int j = 0; j < workers; ++j) {
      const int part = (w + j) % workers, part_end = first + (part + 1) * n / workers;
      std::atomic<int>& next = group_next_[static_cast<std::size_t>(g * workers + part)].index;
      // Look before claiming: an exhausted part is polled often and must not count up forever.
      if (next.load(std::memory_order_relaxed) >= part_end) continue;
      const int i = next.fetch_add(1, std::memory_order_acq_rel);
      if (i >= part_end) continue;
      const auto e = static_cast<std::size_t>(i);
      try {
        finish_env(i, envs_[e]->step_into(sent_actions_[e], batch_.column(i)));
      } catch (...) {
        env_errors_[e] = std::current_exception();
      }
      // This worker's own count: the caller reads it, nobody else writes it.
      std::atomic<long long>& done = group_done_[static_cast<std::size_t>(g * workers + w)].done;
      done.store(done.load(std::memory_order_relaxed) + 1, std::memory_order_release);
      return g;
    }
  }
  return -1;
}

void VecEnv::start_pipeline() {
  stop_pipeline_.store(false);
  pipeline_job_ = [this](int w) {
    int group = 0;  // where this worker last found work: the groups come in turn from there
    for (;;) {
      const std::uint64_t seen = posts_.load();
      if (const int g = step_one_sent(w, group); g >= 0) {
        group = g;
        continue;
      }
      if (stop_pipeline_.load()) return;
      // Nothing to claim: poll briefly (the next send is usually microseconds away), then sleep
      // until a send or the stop, so that an update running meanwhile gets the core.
      if (!spin_until([&] { return posts_.load(std::memory_order_relaxed) != seen; })) posts_.wait(seen);
    }
  };
  pool_.start(pipeline_job_);
  pipeline_running_ = true;
}

// Lets the workers finish every env step still claimable, then ends their job.
void VecEnv::stop_pipeline() {
  if (!pipeline_running_) return;
  pipeline_running_ = false;
  stop_pipeline_.store(true);
  posts_.fetch_add(1);
  posts_.notify_all();
  pool_.join();  // the job itself does not throw: env errors are kept per env
}

const std::vector<EnvStep>& VecEnv::recv(int group) {
  if (in_flight_ == 0 || group != next_recv_)
    throw Error("VecEnv::recv: group " + std::to_string(group) + " received out of turn (next: " +
                std::to_string(next_recv_) + ", " + std::to_string(in_flight_) + " in flight)");
  const int first = group_first(group), end = group_end(group);
  const std::vector<bool>& active = group_active_[static_cast<std::size_t>(group)];
  std::exception_ptr error;
  if (group_overlaps_[static_cast<std::size_t>(group)]) {
    const auto finished = [&] {
      long long done = 0;
      for (int w = 0; w < pool_.size(); ++w)
        done += group_done_[static_cast<std::size_t>(group * pool_.size() + w)].done.load(std::memory_order_acquire);
      return done >= group_expected_[static_cast<std::size_t>(group)];
    };
    while (!finished())
      if (step_one_sent(0, group) < 0) cpu_relax();
    for (int i = first; i < end && !error; ++i) std::swap(error, env_errors_[static_cast<std::size_t>(i)]);
    for (int i = first; i < end; ++i) env_errors_[static_cast<std::size_t>(i)] = nullptr;
  } else {
    try {
      dispatch(sent_actions_, active);
    } catch (...) {
      error = std::current_exception();
    }
  }
  next_recv_ = (group + 1) % groups_;
  if (--in_flight_ == 0) stop_pipeline();
  if (error) std::rethrow_exception(error);
  // The round's timestep, as step() would record it after stepping every env once.
  if (group == 0) round_base_ = timesteps_;
  timesteps_ += end - first;
  record(first, end, active, round_base_ + size());
  return results_;
}

}  // namespace rdsim
