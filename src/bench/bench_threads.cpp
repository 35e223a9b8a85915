// `rdsim bench-fps --threads N` / `--scaling`: total env steps/s of a VecEnv on 1..N threads,
// the speed-up over one thread, and the pool's cost per env step against a plain loop, all
// measured in one run with the runs of every thread count interleaved (so that a machine
// whose load drifts slows them all alike).
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <new>
#include <thread>

#include "bench_util.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/assert.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/worker_pool.hpp"

namespace rdsim::bench {
namespace {

constexpr std::uint64_t kSeed = 12345;

// 1, 2, 4, ... and every core (--scaling); 1 and N (--threads N).
std::vector<int> thread_counts(const BenchFpsOptions& o) {
  std::vector<int> counts = {1};
  if (o.scaling) {
    const int cores = available_cores();
    for (int t = 2; t < cores; t *= 2) counts.push_back(t);
    if (cores > 1) counts.push_back(cores);
  }
  if (o.threads > 1 && std::find(counts.begin(), counts.end(), o.threads) == counts.end()) counts.push_back(o.threads);
  std::sort(counts.begin(), counts.end());
  return counts;
}

std::vector<std::unique_ptr<Env>> make_envs(const Case& c, int n) {
  std::vector<std::unique_ptr<Env>> envs;
  const EnvConfig config = case_config(c);
  for (int i = 0; i < n; ++i) envs.push_back(make_env(config));
  return envs;
}

// The baseline: the same envs stepped one after another on this thread, each writing into its
// batch column and reset when its episode ends, with no pool and no episode bookkeeping.
class PlainLoop {
public:
  PlainLoop(std::vector<std::unique_ptr<Env>> envs) : envs_(std::move(envs)) {
    batch_.resize(envs_.front()->spec().observation, static_cast<int>(envs_.size()));
    for (std::size_t i = 0; i < envs_.size(); ++i)
      envs_[i]->reset_into(batch_.column(static_cast<int>(i)), kSeed + i);
  }
  int size() const { return static_cast<int>(envs_.size()); }
  void step(const std::vector<Action>& actions) {
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      const StepOutcome o = envs_[i]->step_into(actions[i], batch_.column(static_cast<int>(i)));
      if (o.terminated || o.truncated) envs_[i]->reset_into(batch_.column(static_cast<int>(i)));
    }
  }

private:
  std::vector<std::unique_ptr<Env>> envs_;
  ObservationBatch batch_;
};

// A VecEnv stepped in groups (VecEnv::send / recv), as an on-policy rollout with env_groups
// steps it: each batch step receives every group's previous step and sends its next one.
class PipelinedVecEnv {
public:
  explicit PipelinedVecEnv(VecEnv& vec) : vec_(vec) {}
  void step(const std::vector<Action>& actions) {
    for (int g = 0; g < vec_.groups(); ++g) {
      if (vec_.in_flight() == vec_.groups()) vec_.recv(g);
      vec_.send(g, actions);
    }
  }
  // Receives the groups still in flight (inside the timed window: their steps are counted).
  void finish() {
    for (int g = 0; vec_.in_flight() > 0; ++g) vec_.recv(g);
  }
  VecEnv& vec() { return vec_; }

private:
  VecEnv& vec_;
};

// Training takes the finished episodes once per update; a VecEnv here every 256 steps as well.
void take_episodes(PlainLoop&) {}
void take_episodes(VecEnv& vec) { vec.episodes().take_finished(); }
void take_episodes(PipelinedVecEnv& p) { p.vec().episodes().take_finished(); }
void finish(PlainLoop&) {}
void finish(VecEnv&) {}
void finish(PipelinedVecEnv& p) { p.finish(); }

// Env steps per second of `batch_steps` steps of every env.
template <class Stepper>
double timed(Stepper& s, const std::vector<std::vector<Action>>& actions, long long batch_steps, int envs) {
  const auto t0 = Clock::now();
  for (long long k = 0; k < batch_steps; ++k) {
    s.step(actions[static_cast<std::size_t>(k) % actions.size()]);
    if (k % 256 == 255) take_episodes(s);
  }
  finish(s);
  return static_cast<double>(batch_steps * envs) / seconds_since(t0);
}

// The machine's own limit: `count` independent processes, each stepping its share of the envs in
// a plain loop, all at the same time (forked here, released together); their summed env steps/s.
// Nothing is shared between them but the machine, so count x the plain loop alone is what no pool
// can beat. 0 when a process could not be started or failed.
double independent_processes(std::vector<PlainLoop>& loops, const std::vector<std::vector<Action>>& actions,
                             long long batch_steps) {
  const int count = static_cast<int>(loops.size());
  struct Shared {
    std::atomic<int> go{0};
    double steps_per_s[64] = {};
  };
  RDSIM_ASSERT(count <= 64, "at most 64 processes");
  void* map = mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) return 0;
  Shared* shared = new (map) Shared;
  std::vector<pid_t> children;
  std::fflush(nullptr);  // nothing buffered twice
  for (int k = 0; k < count; ++k) {
    const pid_t pid = fork();
    if (pid == 0) {
      while (shared->go.load(std::memory_order_acquire) == 0) {}
      double rate = 0;
      try {
        rate = timed(loops[static_cast<std::size_t>(k)], actions, batch_steps, loops[static_cast<std::size_t>(k)].size());
      } catch (...) {
      }
      shared->steps_per_s[k] = rate;
      _exit(0);
    }
    if (pid > 0) children.push_back(pid);
  }
  shared->go.store(1, std::memory_order_release);
  for (pid_t pid : children) waitpid(pid, nullptr, 0);
  double total = 0;
  bool complete = static_cast<int>(children.size()) == count;
  for (int k = 0; k < count; ++k) {
    complete = complete && shared->steps_per_s[k] > 0;
    total += shared->steps_per_s[k];
  }
  munmap(map, sizeof(Shared));
  return complete ? total : 0;
}

// Nanoseconds for one cache line to go from this thread to another and back (an atomic flag
// passed to and fro, `trips` times): what every hand-over between two workers costs on this
// machine at this moment. On a virtual machine it depends on where the host runs the two CPUs.
double cache_line_round_trip_ns(int trips = 100000) {
  struct alignas(64) Flag {
    std::atomic<int> value{0};
  } flag;
  std::thread other([&] {
    for (int i = 0; i < trips; ++i) {
      while (flag.value.load(std::memory_order_acquire) != 2 * i + 1) {}
      flag.value.store(2 * i + 2, std::memory_order_release);
    }
  });
  const auto t0 = Clock::now();
  for (int i = 0; i < trips; ++i) {
    flag.value.store(2 * i + 1, std::memory_order_release);
    while (flag.value.load(std::memory_order_acquire) != 2 * i + 2) {}
  }
  const double ns = seconds_since(t0) * 1e9 / trips;
  other.join();
  return ns;
}

struct ThreadRow {
  int threads = 1;
  bool processes = false;  // workers 2.. are processes
  int groups = 1;          // VecEnv::groups(): stepped with send / recv when above 1
  std::vector<double> runs;
  double steps_per_s = 0;
};

struct CaseResult {
  Case c;
  int envs = 0;
  std::vector<double> plain_runs;
  double plain_per_s = 0;
  std::vector<ThreadRow> rows;
  // Per thread count above 1: independent processes, each with its share of the envs.
  struct Processes {
    int count = 0;
    std::vector<double> runs;
    double steps_per_s = 0;
  };
  std::vector<Processes> limits;
  std::vector<double> round_trip_runs;  // cache_line_round_trip_ns before each run (with 2+ threads)

  // What VecEnv on one thread adds to each env step over the plain loop, in nanoseconds.
  double overhead_ns() const { return 1e9 / rows.front().steps_per_s - 1e9 / plain_per_s; }
};

CaseResult measure(const Case& c, const std::vector<int>& counts, int envs, const BenchFpsOptions& o) {
  CaseResult result{c, envs, {}, 0, {}, {}, {}};
  PlainLoop plain(make_envs(c, envs));
  // Built before any pool thread exists: t loops of envs / t envs each (the first ones take the rest).
  std::vector<std::vector<PlainLoop>> shares;
  for (int t : counts) {
    if (t == 1 || t > 64 || t > envs) continue;
    shares.emplace_back();
    for (int k = 0; k < t; ++k) shares.back().emplace_back(make_envs(c, envs / t + (k < envs % t ? 1 : 0)));
    result.limits.push_back({t, {}, 0});
  }
  std::vector<std::unique_ptr<VecEnv>> vecs;
  // Where training's env_workers "auto" picks processes, the same counts on threads too: the
  // comparison in one run.
  const bool processes = auto_env_workers(case_config(c)) == EnvWorkers::processes;
  // On threads, also in two pipelined groups (the config's env_groups: 2), for envs whose groups
  // overlap (any worker may step them; others would step one group at a time).
  const bool overlapping = make_envs(c, 1).front()->steps_on_any_thread();
  for (int t : counts) {
    for (int variant = 0; variant < 3; ++variant) {
      const bool p = variant == 2, pipelined = variant == 1;
      if (p && (t == 1 || !processes)) continue;
      if (pipelined && (t == 1 || envs < 2 || !overlapping)) continue;
      vecs.push_back(std::make_unique<VecEnv>(make_envs(c, envs), kSeed, 20, t,
                                              p ? EnvWorkers::processes : EnvWorkers::threads));
      if (pipelined) vecs.back()->set_groups(2);
      result.rows.push_back({vecs.back()->num_threads(), p, vecs.back()->groups(), {}, 0});
    }
  }
  // Random actions drawn before any clock starts: up to 512 batches, reused in turn.
  const long long batch_steps = std::max<long long>(1, (o.steps + envs - 1) / envs);
  std::vector<std::vector<Action>> actions;
  Rng rng = Rng::derive(kSeed, 1);
  for (long long k = 0; k < std::min<long long>(batch_steps, 512); ++k) {
    actions.emplace_back();
    for (int i = 0; i < envs; ++i) actions.back().push_back(random_action(vecs.front()->spec().action, rng));
  }
  const long long warmup = std::max<long long>(batch_steps / 10, 10);
  const auto timed_row = [&](std::size_t k, long long steps) {
    if (vecs[k]->groups() == 1) return timed(*vecs[k], actions, steps, envs);
    PipelinedVecEnv pipelined(*vecs[k]);
    return timed(pipelined, actions, steps, envs);
  };
  timed(plain, actions, warmup, envs);
  for (std::size_t k = 0; k < vecs.size(); ++k) timed_row(k, warmup);
  for (int r = 0; r < o.runs; ++r) {
    if (counts.back() > 1) result.round_trip_runs.push_back(cache_line_round_trip_ns());
    result.plain_runs.push_back(timed(plain, actions, batch_steps, envs));
    for (std::size_t k = 0; k < vecs.size(); ++k) result.rows[k].runs.push_back(timed_row(k, batch_steps));
    // Each process steps every one of its envs batch_steps times, as the pool does.
    for (std::size_t k = 0; k < shares.size(); ++k)
      result.limits[k].runs.push_back(independent_processes(shares[k], actions, batch_steps));
  }
  for (auto& l : result.limits) l.steps_per_s = median(l.runs);
  result.plain_per_s = median(result.plain_runs);
  for (auto& row : result.rows) row.steps_per_s = median(row.runs);
  return result;
}

void print(std::FILE* out, const std::vector<CaseResult>& results, const BenchFpsOptions& o) {
  std::fprintf(out, "\nrdsim bench-fps --%s: total env steps/s of a VecEnv, random actions, resets included\n",
               o.scaling ? "scaling" : "threads");
  std::fprintf(out, "median of %d runs x %lld env steps (all envs together), runs of every row interleaved; "
               "%d cores available to this process\n\n", o.runs, o.steps, available_cores());
  std::fprintf(out, "%-16s %-13s %9s %6s %11s %12s %9s %s\n", "env", "observation", "image", "envs", "workers",
               "steps/s", "speed-up", "  as");
  for (const auto& r : results) {
    const std::string image = image_label(r.c.image_size, r.c.image_channels);
    std::fprintf(out, "%-16s %-13s %9s %6d %11s %12.0f %9s\n", r.c.entry->name.c_str(), r.c.mode.c_str(),
                 image.c_str(), r.envs, "plain loop", r.plain_per_s, "-");
    for (const auto& t : r.rows) {
      const char* as = t.threads == 1         ? ""
                       : t.processes          ? "  this thread + processes"
                       : t.groups > 1         ? "  threads, 2 groups in turn (env_groups)"
                                              : "  threads";
      std::fprintf(out, "%-16s %-13s %9s %6d %11d %12.0f %8.2fx%s\n", r.c.entry->name.c_str(), r.c.mode.c_str(),
                   image.c_str(), r.envs, t.threads, t.steps_per_s, t.steps_per_s / r.rows.front().steps_per_s, as);
    }
    for (const auto& l : r.limits) {
      const std::string label = std::to_string(l.count) + " alone";
      std::fprintf(out, "%-16s %-13s %9s %6d %11s %12.0f %8.2fx  independent processes (the machine's limit)\n",
                   r.c.entry->name.c_str(), r.c.mode.c_str(), image.c_str(), r.envs, label.c_str(), l.steps_per_s,
                   l.steps_per_s / r.plain_per_s);
    }
  }
  std::fputs("\nspeed-up: steps/s over those of 1 thread in the same run.\n"
             "plain loop: the same envs stepped one after another on one thread, no pool, no episode bookkeeping.\n"
             "N alone: N processes stepping their share of the envs in plain loops at the same time, nothing\n"
             "  shared but the machine; their speed-up is over the plain loop.\n"
             "workers: the training config's num_threads. Pixel envs drawn by osmesa are measured on threads and\n"
             "  on worker processes (what env_workers \"auto\" picks for them: Mesa's llvmpipe draws one frame\n"
             "  at a time per process).\n"
             "2 groups in turn: the envs in two halves, each sent to the workers as soon as it is received, so\n"
             "  that no worker waits for the other's last env at each batch step (a rollout with env_groups 2).\n"
             "Pool overhead per env step, VecEnv on 1 thread vs the plain loop:\n",
             out);
  for (const auto& r : results) {
    std::fprintf(out, "  %-16s %-13s %9s %+8.0f ns (%.0f vs %.0f ns per env step)\n", r.c.entry->name.c_str(),
                 r.c.mode.c_str(), image_label(r.c.image_size, r.c.image_channels).c_str(), r.overhead_ns(),
                 1e9 / r.rows.front().steps_per_s, 1e9 / r.plain_per_s);
  }
  for (const auto& r : results) {
    if (r.round_trip_runs.empty()) continue;
    const auto [low, high] = std::minmax_element(r.round_trip_runs.begin(), r.round_trip_runs.end());
    std::fprintf(out, "Cache line round trip between two threads, before each run of %s %s: median %.0f ns (%.0f-%.0f).\n"
                 "Workers hand each other cache lines at every batch step (actions, results, the step's start and "
                 "end);\nindependent processes do not.\n",
                 r.c.entry->name.c_str(), r.c.mode.c_str(), median(r.round_trip_runs), *low, *high);
  }
}

nlohmann::json to_json(const std::vector<CaseResult>& results, const BenchFpsOptions& o) {
  nlohmann::json j = {{"runs", o.runs}, {"steps_per_run", o.steps}, {"cores", available_cores()},
                      {"rows", nlohmann::json::array()}};
  for (const auto& r : results) {
    nlohmann::json threads = nlohmann::json::array();
    for (const auto& t : r.rows)
      threads.push_back({{"threads", t.threads}, {"env_workers", t.processes ? "processes" : "threads"}, {"env_groups", t.groups},
                         {"steps_per_s", t.steps_per_s}, {"runs_steps_per_s", t.runs},
                         {"speedup", t.steps_per_s / r.rows.front().steps_per_s}});
    nlohmann::json limits = nlohmann::json::array();
    for (const auto& l : r.limits)
      limits.push_back({{"processes", l.count}, {"steps_per_s", l.steps_per_s}, {"runs_steps_per_s", l.runs},
                        {"speedup_over_plain_loop", l.steps_per_s / r.plain_per_s}});
    j["rows"].push_back({{"env", r.c.entry->name}, {"observation", r.c.mode}, {"independent_processes", limits},
                         {"image_size", r.c.image_size > 0 ? nlohmann::json(r.c.image_size) : nlohmann::json(nullptr)},
                         {"image_channels", r.c.image_size > 0 ? nlohmann::json(r.c.image_channels) : nlohmann::json(nullptr)},
                         {"envs", r.envs}, {"plain_loop_steps_per_s", r.plain_per_s},
                         {"plain_loop_runs_steps_per_s", r.plain_runs}, {"threads", threads},
                         {"pool_overhead_ns_per_step", r.overhead_ns()},
                         {"cache_line_round_trip_ns_runs", r.round_trip_runs}});
  }
  return j;
}

}  // namespace

int threads_command(const std::vector<Case>& cases, const BenchFpsOptions& o) {
  const std::vector<int> counts = thread_counts(o);
  const int envs = o.num_envs > 0 ? o.num_envs : 4 * counts.back();
  std::vector<CaseResult> results;
  for (const Case& c : cases) {
    announce(c);
    try {
      results.push_back(measure(c, counts, envs, o));
    } catch (const Error& e) {
      std::fprintf(stderr, "bench-fps: skipping %s / %s: %s\n", c.entry->name.c_str(), c.mode.c_str(), e.what());
    }
  }
  if (results.empty()) throw Error("bench-fps: nothing could be measured for the given --env/--mode");
  print(table_stream(o.json_path), results, o);
  write_bench_json(o.json_path, to_json(results, o));
  return 0;
}

}  // namespace rdsim::bench
