// Scale (issue #15): the same results on any number of threads, data-parallel training under
// mpirun, and the pieces of the MPI run that can be checked without MPI.
#include <catch2/catch.hpp>
#include <cstring>
#include <sstream>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/training/data_parallel.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/render/renderer.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::ScratchDir;

namespace {

std::string cartpole_config(const ScratchDir& dir, long long interval = 0) {
  const std::string path = dir / "cartpole.json";
  rltest::spit(path, R"({
    "algorithm": "ppo", "env": {"name": "cartpole"}, "seed": 3, "total_timesteps": 4096,
    "num_envs": 4, "checkpoint_interval": )" + std::to_string(interval) + R"(, "sync_check_interval": 1,
    "network": {"hidden_sizes": [32, 32]},
    "ppo": {"n_steps": 64, "batch_size": 128, "n_epochs": 4, "learning_rate": 0.001, "gamma": 0.98, "gae_lambda": 0.8}
  })");
  return path;
}

std::string jaka_config(const ScratchDir& dir) {
  const std::string path = dir / "jaka.json";
  rltest::spit(path, R"({
    "algorithm": "ppo", "env": {"name": "jaka_button", "random_target": true}, "seed": 2,
    "total_timesteps": 2048, "num_envs": 8, "stats_window": 10,
    "network": {"hidden_sizes": [32, 32]},
    "ppo": {"n_steps": 64, "batch_size": 128, "n_epochs": 2, "learning_rate": 0.003}
  })");
  return path;
}


}  // namespace

TEST_CASE("train: the same CSV and weights on 1 and 2 threads", "[cli][threads]") {
  ScratchDir dir("threads");
  for (const std::string& config : {cartpole_config(dir), jaka_config(dir)}) {
    for (const std::string threads : {"1", "2"}) {
      const std::string run = dir / "t";
      const auto r = rltest::run_rdsim("train --quiet --config " + config + " --threads " + threads + " --overwrite --log-dir " +
                                           run + threads, dir);
      INFO(r.err);
      REQUIRE(r.exit_code == 0);
    }
    CHECK(rltest::run_logs(dir / "t1") == rltest::run_logs(dir / "t2"));
    CHECK(rltest::lines(rltest::slurp(dir / "t1/episodes.csv")).size() > 5);
    CHECK_THAT(rltest::slurp(dir / "t2/config.json"), Contains("\"num_threads\": 2"));
  }
}

TEST_CASE("train: pixel envs in worker processes give the CSV and weights of one thread", "[cli][threads][pixels]") {
  ScratchDir dir("env_processes");
  const std::string config = dir / "pixels.json";
  rltest::spit(config, R"({
    "algorithm": "ppo", "env": {"name": "jaka_button", "observation": "raw_pixels", "image_width": 32,
    "image_height": 32, "random_target": true, "max_steps": 20}, "seed": 4, "total_timesteps": 256, "num_envs": 4,
    "stats_window": 5, "network": {"cnn": {"preset": "small"}},
    "ppo": {"n_steps": 32, "batch_size": 64, "n_epochs": 1}
  })");
  for (const std::string threads : {"1", "2"}) {
    const auto r = rltest::run_rdsim("train --quiet --config " + config + " --threads " + threads + " --log-dir " +
                                         (dir / ("t" + threads)), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(rltest::run_logs(dir / "t1") == rltest::run_logs(dir / "t2"));
  CHECK(rltest::lines(rltest::slurp(dir / "t1/episodes.csv")).size() > 5);
  CHECK_THAT(rltest::slurp(dir / "t2/config.json"), Contains("\"env_workers\": \"auto\""));
  // A remote env cannot be forked: asking for processes is refused, with the key named.
  rdsim::TrainConfig remote;
  remote.remote.remote = "tcp://127.0.0.1:7777";
  CHECK(rdsim::resolve_env_workers(remote) == rdsim::EnvWorkers::threads);
  remote.env_workers = "processes";
  CHECK_THROWS_WITH(rdsim::resolve_env_workers(remote), Contains("env_workers"));
  rdsim::TrainConfig pixels;
  pixels.env.observation = rdsim::ObservationMode::RawPixels;
  CHECK(rdsim::resolve_env_workers(pixels) == rdsim::EnvWorkers::processes);
  pixels.env_workers = "threads";
  CHECK(rdsim::resolve_env_workers(pixels) == rdsim::EnvWorkers::threads);
  pixels.env.renderer = "egl";
  CHECK(rdsim::resolve_env_workers(pixels) == rdsim::EnvWorkers::threads);
  pixels.env_workers = "auto";
  CHECK(rdsim::resolve_env_workers(pixels) == rdsim::EnvWorkers::threads);
  pixels.env_workers = "processes";
  CHECK_THROWS_WITH(rdsim::resolve_env_workers(pixels), Contains("\"renderer\": \"osmesa\""));
}

TEST_CASE("VecEnv: pixel envs render the same images on 1 and 3 threads or worker processes", "[threads][pixels]") {
  // Every backend built here that can make a context: the renderers are made on this thread and
  // draw on the workers (an egl context binds to one thread: the strict case).
  std::vector<std::string> backends;
  for (const std::string& b : rdsim::renderer_backends()) {
    try {
      rdsim::make_renderer(b, 8, 8);
      backends.push_back(b);
    } catch (const rdsim::Error& e) {
      WARN("renderer " << b << " unavailable here: " << e.what());
    }
  }
  REQUIRE(!backends.empty());
  const std::string backend = GENERATE_COPY(from_range(backends));
  INFO("renderer " << backend);
  rdsim::EnvConfig config = rdsim::default_env_config("jaka_button");
  config.renderer = backend;
  config.observation = rdsim::ObservationMode::RawPixels;
  config.image_width = config.image_height = 32;
  config.get<rdsim::ReachOptions>().random_target = true;
  auto envs = [&] {
    std::vector<std::unique_ptr<rdsim::Env>> v;
    for (int i = 0; i < 3; ++i) v.push_back(rdsim::make_env(config));
    return v;
  };
  // Threads, or (what env_workers "auto" picks for osmesa) this thread and two worker processes.
  const rdsim::EnvWorkers workers = GENERATE(rdsim::EnvWorkers::threads, rdsim::EnvWorkers::processes);
  if (workers == rdsim::EnvWorkers::processes && rdsim::auto_env_workers(config) != workers) return;  // a GPU context is not forked
  INFO((workers == rdsim::EnvWorkers::processes ? "processes" : "threads"));
  rdsim::VecEnv one(envs(), 4, 20, 1), three(envs(), 4, 20, 3, workers);
  REQUIRE(three.num_threads() == 3);
  rdsim::Rng rng(1);
  std::vector<rdsim::Action> actions(3);
  for (int t = 0; t < 60; ++t) {
    for (auto& a : actions) a = rdsim::Action::discrete(static_cast<int>(rng.below(6)));
    const auto& a = one.step(actions);
    const auto& b = three.step(actions);
    REQUIRE(one.observations().pixels == three.observations().pixels);
    for (int i = 0; i < 3; ++i) {
      CHECK(a[static_cast<std::size_t>(i)].reward == b[static_cast<std::size_t>(i)].reward);
      if (a[static_cast<std::size_t>(i)].done())
        CHECK(a[static_cast<std::size_t>(i)].final_observation.pixels == b[static_cast<std::size_t>(i)].final_observation.pixels);
    }
  }
  CHECK(one.observations().pixels.cast<int>().sum() > 0);
}

namespace {

// Two ranks whose weight hashes differ (rank 1's is rank 0's + 1).
class DivergedRanks final : public rdsim::Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 2; }
  int local_size() const override { return 2; }
  std::string name() const override { return "diverged"; }
  [[noreturn]] void abort(int code) override { std::exit(code); }

protected:
  void do_allreduce_sum(float*, std::size_t) override {}
  void do_allreduce_sum(double*, std::size_t) override {}
  void do_allgather(const void* send, std::size_t bytes, void* recv) override {
    std::memcpy(recv, send, bytes);
    std::uint64_t other;
    std::memcpy(&other, send, sizeof other);
    ++other;
    std::memcpy(static_cast<char*>(recv) + bytes, &other, sizeof other);
  }
  void do_broadcast(std::string&, int) override {}
  std::vector<std::string> do_gather(const std::string& b, int) override { return {b, b}; }
};

}  // namespace

TEST_CASE("data parallel: diverged weights stop the run with a clear error", "[mpi]") {
  rdsim::AlgorithmConfig c;
  c.params = rdsim::PpoConfig{};
  auto env = rdsim::make_env(rdsim::default_env_config("cartpole"));
  auto algo = rdsim::make_algorithm(c, 1, env->spec());
  DivergedRanks comm;
  CHECK_THROWS_WITH(rdsim::check_same_weights(comm, *algo, 30),
                    Contains("weights of rank 1 differ from rank 0's after update 30"));
  rdsim::check_same_weights(rdsim::single_process_communicator(), *algo, 30);  // nothing to compare
  CHECK(rdsim::rank_seed(7, 0) == 7);
  CHECK(rdsim::rank_seed(7, 1) != rdsim::rank_seed(7, 2));
}

TEST_CASE("train: num_threads is checked and resolved", "[threads]") {
  rdsim::TrainConfig c;
  c.num_envs = 8;
  c.num_threads = 3;
  CHECK(rdsim::resolve_num_threads(c, 1) == 3);
  c.num_threads = 100;
  CHECK(rdsim::resolve_num_threads(c, 1) == 8);  // at most one thread per env
  c.num_threads = 0;
  const int automatic = rdsim::resolve_num_threads(c, 1);
  CHECK(automatic >= 1);
  CHECK(automatic <= 8);
  CHECK(rdsim::resolve_num_threads(c, 64) >= 1);
  ScratchDir dir("threads_bad");
  rltest::spit(dir / "bad.json", R"({"env": {"name": "cartpole"}, "num_threads": -1})");
  const auto r = rltest::run_rdsim("train --config " + (dir / "bad.json"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("num_threads"));
}

#ifdef RDSIM_MPIEXEC
TEST_CASE("mpirun -np 2: the same CSV twice, the steps of both ranks, weights checked every update", "[cli][mpi]") {
  ScratchDir dir("mpi_determinism");
  const std::string config = cartpole_config(dir);
  for (const char* run : {"a", "b"}) {
    const auto r = rltest::run_rdsim_mpi(2, "train --quiet --config " + config + " --log-dir " + (dir / run), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(rltest::lines(r.out).size() == 2);  // --quiet keeps the summary: rank 0's run and MPI lines
    CHECK_THAT(r.out, Contains("2 MPI ranks"));
  }
  CHECK(rltest::run_logs(dir / "a") == rltest::run_logs(dir / "b"));
  const auto progress = rltest::lines(rltest::slurp(dir / "a/progress.csv"));
  CHECK_THAT(progress.front(), Contains("allreduce_bytes"));
  CHECK(progress.size() == 1 + 4096 / (2 * 4 * 64));  // one row per update, steps of both ranks
  CHECK(progress.back().rfind("4096,", 0) == 0);
  // Episodes of both ranks, numbered in order.
  const auto episodes = rltest::lines(rltest::slurp(dir / "a/episodes.csv"));
  REQUIRE(episodes.size() > 3);
  for (std::size_t k = 1; k < episodes.size(); ++k) CHECK(episodes[k].rfind(std::to_string(k) + ",", 0) == 0);

  // The same config as one process is a different (half as wide) run.
  const auto one = rltest::run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "one"), dir);
  REQUIRE(one.exit_code == 0);
  CHECK(rltest::run_logs(dir / "one").progress != rltest::run_logs(dir / "a").progress);
}

TEST_CASE("mpirun -np 2: --resume continues exactly like an uninterrupted run", "[cli][mpi]") {
  ScratchDir dir("mpi_resume");
  const std::string config = cartpole_config(dir, 1024);
  auto r = rltest::run_rdsim_mpi(2, "train --quiet --config " + config + " --timesteps 6144 --log-dir " + (dir / "full"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  r = rltest::run_rdsim_mpi(2, "train --quiet --config " + config + " --log-dir " + (dir / "part"), dir);
  REQUIRE(r.exit_code == 0);
  r = rltest::run_rdsim_mpi(2, "train --quiet --resume " + (dir / "part") + " --timesteps 6144", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::run_logs(dir / "part") == rltest::run_logs(dir / "full"));

  // A checkpoint of two ranks needs two ranks.
  r = rltest::run_rdsim("train --quiet --resume " + (dir / "part"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("resume it with mpirun -np 2"));
}

TEST_CASE("mpirun -np 2: SAC trains data-parallel", "[cli][mpi]") {
  ScratchDir dir("mpi_algorithms");
  rltest::spit(dir / "sac.json", R"({
    "algorithm": "sac", "env": {"name": "pendulum"}, "seed": 1, "total_timesteps": 800, "num_envs": 2,
    "sync_check_interval": 1, "network": {"hidden_sizes": [16, 16]},
    "sac": {"learning_starts": 100, "batch_size": 32, "buffer_size": 1000}
  })");
  auto r = rltest::run_rdsim_mpi(2, "train --quiet --config " + (dir / "sac.json") + " --log-dir " + (dir / "sac"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);  // the critics' weights too are compared across the ranks every update
  const auto progress = rltest::lines(rltest::slurp(dir / "sac/progress.csv"));
  CHECK_THAT(progress.front(), Contains("allreduce_bytes"));
  CHECK(progress.back().rfind("800,", 0) == 0);
}

TEST_CASE("mpirun -np 2: TRPO, ARS and CMA-ES train data-parallel, the same CSV twice", "[cli][mpi]") {
  ScratchDir dir("mpi_trpo_search");
  // TRPO averages g, the Fisher-vector products, surrogate/KL and critic gradients; ARS and CMA-ES
  // share out their population (CMA-ES's 5 candidates unevenly: 2 and 3). sync_check_interval 1:
  // the weights (and the search state) are compared across the ranks after every update.
  const std::pair<const char*, const char*> configs[] = {
      {"trpo", R"("trpo": {"n_steps": 64, "batch_size": 64, "n_critic_updates": 2, "cg_max_steps": 5})"},
      {"ars", R"("ars": {"n_delta": 3, "n_top": 2, "delta_std": 0.1})"},
      {"cma_es", R"("cma_es": {"population_size": 5, "sigma": 0.3})"}};
  for (const auto& [name, section] : configs) {
    INFO(name);
    const std::string config = dir / (std::string(name) + ".json");
    rltest::spit(config, std::string(R"({"algorithm": ")") + name + R"(", "env": {"name": "cartpole"}, "seed": 4,
      "total_timesteps": 2000, "num_envs": 2, "sync_check_interval": 1, "network": {"hidden_sizes": []}, )" +
                             section + "}");
    for (const char* run : {"a", "b"}) {
      const auto r = rltest::run_rdsim_mpi(2, "train --quiet --config " + config + " --log-dir " + (dir / (std::string(name) + run)), dir);
      INFO(r.err);
      REQUIRE(r.exit_code == 0);
    }
    const std::string a = dir / (std::string(name) + "a"), b = dir / (std::string(name) + "b");
    CHECK(rltest::run_logs(a) == rltest::run_logs(b));
    const auto progress = rltest::lines(rltest::slurp(a + "/progress.csv"));
    REQUIRE(progress.size() > 2);
    CHECK(std::stoll(progress.back()) >= 2000);  // the steps of both ranks
    const auto episodes = rltest::lines(rltest::slurp(a + "/episodes.csv"));
    REQUIRE(episodes.size() > 3);
    for (std::size_t k = 1; k < episodes.size(); ++k) CHECK(episodes[k].rfind(std::to_string(k) + ",", 0) == 0);
    if (std::string(name) == "trpo") continue;
    // Whole episodes only: their timesteps rise and end at the run's steps.
    const auto timesteps = [&](std::size_t k) { return std::stoll(episodes[k].substr(episodes[k].find(',') + 1)); };
    for (std::size_t k = 2; k < episodes.size(); ++k) CHECK(timesteps(k) > timesteps(k - 1));
    CHECK(timesteps(episodes.size() - 1) == std::stoll(progress.back()));
  }
}

TEST_CASE("mpirun -np 2: a config error is reported once, and every rank exits with its status", "[cli][mpi]") {
  // rdsim's lines in the job's stderr (mpirun adds its own note on a non-zero exit status).
  const auto rdsim_lines = [](const std::string& err) {
    int n = 0;
    for (const auto& line : rltest::lines(err)) n += line.rfind("rdsim", 0) == 0 ? 1 : 0;
    return n;
  };
  ScratchDir dir("mpi_config_error");
  rltest::spit(dir / "bad.json", R"({"algorithm": "ppo", "env": {"name": "cartpole"}, "bogus_key": 1})");
  auto r = rltest::run_rdsim_mpi(2, "train --quiet --config " + (dir / "bad.json") + " --log-dir " + (dir / "bad"), dir);
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(rdsim_lines(r.err) == 1);  // rank 0's; rank 1 leaves quietly
  CHECK_THAT(r.err, Contains("bogus_key: unknown key"));
  CHECK_THAT(r.err, !Contains("MPI_ABORT"));  // every rank returns: no abort, no killed rank
  // An error every rank meets (the algorithm refuses the config on each): once too.
  rltest::spit(dir / "trpo.json", R"({"algorithm": "trpo", "env": {"name": "cartpole"}, "network": {"shared": true}})");
  r = rltest::run_rdsim_mpi(2, "train --quiet --config " + (dir / "trpo.json") + " --log-dir " + (dir / "trpo"), dir);
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(rdsim_lines(r.err) == 1);
  CHECK_THAT(r.err, Contains("needs separate policy and value networks"));
  CHECK_THAT(r.err, !Contains("MPI_ABORT"));
}
#endif
