// VecEnv on several threads, and the data-parallel hooks of the algorithms (with a stand-in
// communicator; the real MPI runs are in tests/app and tests/mpi).
#include <catch2/catch.hpp>
#include <sstream>
#include <unistd.h>
#include <utility>

#include "rdsim/algorithms/flat_policy.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/algorithms/population.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_setup.hpp"
#include "fake_communicator.hpp"
#include "toy_env.hpp"

namespace {

// The weights the ranks share (a training state also holds Rng bytes with padding, so it is not
// compared whole).
std::string weights(const rdsim::Algorithm& algo) {
  std::ostringstream out;
  algo.save_all_weights(out);
  return out.str();
}

// Two VecEnvs' results of one step agree env by env.
void check_same_steps(const std::vector<rdsim::EnvStep>& a, const std::vector<rdsim::EnvStep>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].reward == b[i].reward);
    CHECK(a[i].terminated == b[i].terminated);
    CHECK(a[i].truncated == b[i].truncated);
    if (a[i].done()) CHECK(a[i].final_observation.values == b[i].final_observation.values);
  }
}

Setup small(const std::string& algorithm) {
  Setup c;
  c.algorithm = algorithm;
  c.seed = 5;
  c.network.hidden_sizes = {16, 16};
  c.ppo.n_steps = 16;
  c.ppo.batch_size = 32;
  c.ppo.n_epochs = 2;
  c.a2c.n_steps = 8;
  c.dqn.learning_starts = 20;
  c.dqn.buffer_size = 500;
  c.dqn.batch_size = 16;
  c.dqn.train_freq = 2;
  auto off_policy = [](auto& o) {
    o.learning_starts = 20;
    o.buffer_size = 500;
    o.batch_size = 16;
    o.train_freq = 2;
  };
  off_policy(c.sac);
  off_policy(c.td3);
  off_policy(c.ddpg);
  return c;
}

}  // namespace

TEST_CASE("VecEnv gives the same steps on 1, 2, 3 and 7 threads", "[vec_env][threads]") {
  std::vector<rdsim::Action> actions;
  for (int i = 0; i < 7; ++i) actions.push_back(rdsim::Action::discrete(i % 2));
  rdsim::VecEnv one(toy::make_envs(7, true, 6, 4), 11, 20, 1);
  // Envs bound to their worker, and envs any worker may step (VecEnv then shares them out).
  for (const bool any_thread : {false, true})
  for (int threads : {2, 3, 7, 64}) {
    INFO((any_thread ? "shared envs, " : "envs on their own worker, ") << threads << " threads");
    auto envs = toy::make_envs(7, true, 6, 4);
    for (auto& e : envs) dynamic_cast<toy::SignEnv&>(*e).any_thread = any_thread;
    rdsim::VecEnv many(std::move(envs), 11, 20, threads);
    CHECK(many.num_threads() == std::min(threads, 7));
    rdsim::VecEnv ref(toy::make_envs(7, true, 6, 4), 11, 20, 1);
    for (int t = 0; t < 40; ++t) {
      const auto& a = ref.step(actions);
      const auto& b = many.step(actions);
      CHECK(ref.observations().values == many.observations().values);
      check_same_steps(a, b);
    }
    const auto ea = ref.episodes().take_finished(), eb = many.episodes().take_finished();
    REQUIRE(ea.size() == eb.size());
    for (std::size_t k = 0; k < ea.size(); ++k) {
      CHECK(ea[k].episode_return == eb[k].episode_return);
      CHECK(ea[k].timesteps == eb[k].timesteps);
    }
  }
  (void)one;
}

namespace {

// An env that rejects action 9, through the plain interface only (VecEnv uses the default
// step_into, which calls step()); its process ends on action 8 (a crash in an env's library, as
// the OS reports it: for worker processes only).
class PickyEnv final : public rdsim::Env {
public:
  PickyEnv() {
    spec_.observation.shape = {1};
    spec_.action.n = 10;
    spec_.max_episode_steps = 3;
  }
  const rdsim::Spec& spec() const override { return spec_; }
  rdsim::Observation reset(std::optional<std::uint64_t> = std::nullopt) override {
    rdsim::Observation o;
    o.values = Eigen::VectorXf::Zero(1);
    return o;
  }
  rdsim::StepResult step(const rdsim::Action& a) override {
    if (a.index == 9) throw rdsim::Error("picky: action 9");
    if (a.index == 8) _exit(3);
    rdsim::StepResult r;
    r.observation.values = Eigen::VectorXf::Constant(1, static_cast<float>(a.index));
    return r;
  }

private:
  rdsim::Spec spec_;
};

}  // namespace

TEST_CASE("VecEnv: an env's error on a worker thread reaches the caller", "[vec_env][threads]") {
  std::vector<std::unique_ptr<rdsim::Env>> envs;
  for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<PickyEnv>());
  rdsim::VecEnv vec(std::move(envs), 1, 20, 2);
  std::vector<rdsim::Action> actions = {rdsim::Action::discrete(1), rdsim::Action::discrete(2),
                                        rdsim::Action::discrete(3), rdsim::Action::discrete(4)};
  vec.step(actions);
  CHECK(vec.observations().values == Eigen::RowVector4f(1, 2, 3, 4));
  actions[3] = rdsim::Action::discrete(9);  // env 3 lives on worker 1
  CHECK_THROWS_WITH(vec.step(actions), "picky: action 9");
}

TEST_CASE("VecEnv in worker processes: the same steps as on one thread", "[vec_env][processes]") {
  using rdsim::EnvWorkers;
  const bool discrete = GENERATE(true, false);
  std::vector<rdsim::Action> actions;
  for (int i = 0; i < 7; ++i)
    actions.push_back(discrete ? rdsim::Action::discrete(i % 2) : rdsim::Action::continuous(toy::vec({0.3f * (i % 3) - 0.3f})));
  for (int workers : {2, 3, 7}) {
    INFO(workers << " workers, discrete " << discrete);
    rdsim::VecEnv ref(toy::make_envs(7, discrete, 6, 4), 11, 20, 1);
    rdsim::VecEnv many(toy::make_envs(7, discrete, 6, 4), 11, 20, workers, EnvWorkers::processes);
    CHECK(many.processes());
    CHECK(many.num_threads() == workers);
    CHECK(ref.observations().values == many.observations().values);
    for (int t = 0; t < 40; ++t) {
      // Now and then only some envs step (the population methods' way).
      std::vector<bool> active(7, true);
      if (t % 5 == 4) active = {true, false, true, false, false, true, true};
      const auto& a = ref.step(actions, active);
      const auto& b = many.step(actions, active);
      REQUIRE(ref.observations().values == many.observations().values);
      check_same_steps(a, b);
    }
    CHECK(ref.timesteps() == many.timesteps());
    const auto ea = ref.episodes().take_finished(), eb = many.episodes().take_finished();
    REQUIRE(ea.size() == eb.size());
    for (std::size_t k = 0; k < ea.size(); ++k) CHECK(ea[k].episode_return == eb[k].episode_return);
    CHECK_THROWS_WITH(many.env(6), Catch::Matchers::Contains("worker process"));
    CHECK(many.env(0).spec().env_name == "sign");  // block 0 is this process's
  }
}

TEST_CASE("VecEnv in worker processes: checkpoints continue identically, across worker kinds", "[vec_env][processes]") {
  using rdsim::EnvWorkers;
  const std::vector<rdsim::Action> actions(4, rdsim::Action::discrete(0));
  rdsim::VecEnv a(toy::make_envs(4, true, 5), 1, 20, 2, EnvWorkers::processes);
  for (int t = 0; t < 7; ++t) a.step(actions);
  a.drop_caches();
  std::stringstream saved;
  a.save(saved);
  // Loaded by processes and by one thread: both continue as `a` does.
  rdsim::VecEnv b(toy::make_envs(4, true, 5), 99, 20, 2, EnvWorkers::processes), c(toy::make_envs(4, true, 5), 98);
  std::stringstream copy(saved.str());
  CHECK(b.load(saved, "test"));
  CHECK(c.load(copy, "test"));
  for (int t = 0; t < 9; ++t) {
    a.step(actions);
    b.step(actions);
    c.step(actions);
    CHECK(a.observations().values == b.observations().values);
    CHECK(a.observations().values == c.observations().values);
  }
}

TEST_CASE("VecEnv in worker processes: an env's error or a dead process reaches the caller", "[vec_env][processes]") {
  using rdsim::EnvWorkers;
  std::vector<rdsim::Action> actions = {rdsim::Action::discrete(1), rdsim::Action::discrete(2),
                                        rdsim::Action::discrete(3), rdsim::Action::discrete(4)};
  SECTION("an exception: its message, and the processes still answer") {
    std::vector<std::unique_ptr<rdsim::Env>> envs;
    for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<PickyEnv>());
    rdsim::VecEnv vec(std::move(envs), 1, 20, 2, EnvWorkers::processes);
    vec.step(actions);
    CHECK(vec.observations().values == Eigen::RowVector4f(1, 2, 3, 4));
    actions[3] = rdsim::Action::discrete(9);  // env 3 lives in the worker process
    CHECK_THROWS_WITH(vec.step(actions), "picky: action 9");
    actions[3] = rdsim::Action::discrete(5);
    vec.step(actions);
    CHECK(vec.observations().values == Eigen::RowVector4f(1, 2, 3, 5));
    actions[0] = rdsim::Action::discrete(9);  // env 0 lives in this process: the worker finishes its share
    CHECK_THROWS_WITH(vec.step(actions), "picky: action 9");
    actions[0] = rdsim::Action::discrete(6);
    vec.step(actions);
    CHECK(vec.observations().values == Eigen::RowVector4f(6, 2, 3, 5));
  }
  SECTION("a process that dies: an error naming its envs, not a hang") {
    std::vector<std::unique_ptr<rdsim::Env>> envs;
    for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<PickyEnv>());
    rdsim::VecEnv vec(std::move(envs), 1, 20, 2, EnvWorkers::processes);
    actions[2] = rdsim::Action::discrete(8);
    CHECK_THROWS_WITH(vec.step(actions), Catch::Matchers::Contains("envs 2-3 (worker process)") &&
                                             Catch::Matchers::Contains("exited with status 3"));
  }  // and the VecEnv is destroyed without waiting for it
  SECTION("a wrong-sized continuous action is refused before it is sent") {
    rdsim::VecEnv vec(toy::make_envs(2, false), 1, 20, 2, EnvWorkers::processes);
    const std::vector<rdsim::Action> bad = {rdsim::Action::continuous(toy::vec({0.1f})),
                                            rdsim::Action::continuous(toy::vec({0.1f, 0.2f}))};
    CHECK_THROWS_WITH(vec.step(bad), "env 1: action of size 2, expected 1");
  }
}

TEST_CASE("every algorithm trains identically with VecEnv threads and worker processes", "[vec_env][processes]") {
  const std::pair<const char*, bool> algorithms[] = {{"ppo", true}, {"dqn", true}, {"cma_es", true}, {"sac", false}};
  for (const auto& [name, discrete] : algorithms) {
    const Setup s = small(name);
    rdsim::VecEnv v1(toy::make_envs(6, discrete, 8), 3, 20, 1),
        vp(toy::make_envs(6, discrete, 8), 3, 20, 3, rdsim::EnvWorkers::processes);
    auto a1 = make_algorithm(s, v1.spec()), ap = make_algorithm(s, vp.spec());
    for (int u = 0; u < 4; ++u) CHECK(a1->update(v1, {v1.timesteps(), 2000}) == ap->update(vp, {vp.timesteps(), 2000}));
    INFO(name);
    CHECK(weights(*a1) == weights(*ap));
  }
}

TEST_CASE("every algorithm trains identically on 1 and 3 VecEnv threads", "[vec_env][threads]") {
  const std::pair<const char*, bool> algorithms[] = {{"ppo", true},  {"a2c", true},  {"dqn", true},    {"trpo", true},
                                                     {"ars", true},  {"cma_es", true}, {"random", true}, {"sac", false},
                                                     {"td3", false}, {"ddpg", false}};
  for (const auto& [name, discrete] : algorithms) {
    const Setup s = small(name);
    rdsim::VecEnv v1(toy::make_envs(6, discrete, 8), 3, 20, 1), v3(toy::make_envs(6, discrete, 8), 3, 20, 3);
    auto a1 = make_algorithm(s, v1.spec()), a3 = make_algorithm(s, v3.spec());
    for (int u = 0; u < 6; ++u) {
      const rdsim::Metrics m1 = a1->update(v1, {v1.timesteps(), 2000});
      const rdsim::Metrics m3 = a3->update(v3, {v3.timesteps(), 2000});
      CHECK(m1 == m3);
    }
    INFO(name);
    CHECK(weights(*a1) == weights(*a3));
  }
}

TEST_CASE("average_gradients: the mean over the ranks, one allreduce of every gradient", "[data_parallel]") {
  rdsim::nn::Tensor a(2, 3), b(4, 1);
  a.grad.setConstant(1.0f);
  b.grad.setConstant(-2.0f);
  const rdsim::nn::ParamList params = {rdsim::nn::param_of(a, "a"), rdsim::nn::param_of(b, "b")};
  std::vector<float> buffer;
  toy::FakeCommunicator comm(4, 3.0f);  // 3 other ranks, each with 3x these gradients
  rdsim::average_gradients(comm, params, buffer);
  CHECK(a.grad.isApproxToConstant((1.0f + 3 * 3.0f) / 4));
  CHECK(b.grad.isApproxToConstant((-2.0f - 3 * 6.0f) / 4));
  CHECK(comm.allreduce_traffic().calls == 1);
  CHECK(comm.allreduce_traffic().bytes == (6 + 4) * 4);
  rdsim::average_gradients(rdsim::single_process_communicator(), params, buffer);  // no-op
  CHECK(b.grad.isApproxToConstant((-2.0f - 3 * 6.0f) / 4));
}

TEST_CASE("data-parallel PPO, A2C, DQN and TRPO: ranks with the same gradients train like one process", "[data_parallel]") {
  for (const char* name : {"ppo", "a2c", "dqn", "trpo"}) {
    INFO(name);
    const Setup s = small(name);
    rdsim::VecEnv v1(toy::make_envs(4, true, 8), 9), v2(toy::make_envs(4, true, 8), 9);
    auto alone = make_algorithm(s, v1.spec()), ranked = make_algorithm(s, v2.spec());
    toy::FakeCommunicator comm(2);  // the other rank has this rank's gradients: their mean is this rank's
    ranked->set_communicator(comm);
    for (int u = 0; u < 8; ++u) {
      alone->update(v1, {v1.timesteps(), 2000});
      ranked->update(v2, {v2.timesteps(), 2000});
    }
    CHECK(weights(*alone) == weights(*ranked));
    CHECK(comm.allreduce_traffic().calls > 0);  // every minibatch / gradient step
  }
}

TEST_CASE("data-parallel SAC and TD3: every optimiser step averages, critics and targets shared", "[data_parallel]") {
  for (const char* name : {"sac", "td3"}) {
    INFO(name);
    const Setup s = small(name);
    rdsim::VecEnv v1(toy::make_envs(2, false, 8), 9), v2(toy::make_envs(2, false, 8), 9);
    auto alone = make_algorithm(s, v1.spec()), ranked = make_algorithm(s, v2.spec());
    REQUIRE(ranked->data_parallel());
    toy::FakeCommunicator comm(2);  // the other rank has this rank's gradients: their mean is this rank's
    ranked->set_communicator(comm);
    for (int u = 0; u < 40; ++u) {
      alone->update(v1, {v1.timesteps(), 2000});
      ranked->update(v2, {v2.timesteps(), 2000});
    }
    CHECK(weights(*alone) == weights(*ranked));
    CHECK(comm.allreduce_traffic().calls > 0);
    // save_all_weights holds more than the model (the critics), and loads back into another copy.
    std::ostringstream model;
    alone->save(model, false);
    CHECK(weights(*alone).size() > model.str().size());
    Setup other = s;
    other.seed = 77;
    auto copy = make_algorithm(other, v1.spec());
    std::istringstream in(weights(*alone));
    copy->load_all_weights(in, "test");
    CHECK(weights(*copy) == weights(*alone));
  }
}

TEST_CASE("every algorithm trains data-parallel (the training loop accepts it under mpirun)", "[data_parallel]") {
  rdsim::VecEnv discrete(toy::make_envs(2, true, 8), 1), box(toy::make_envs(2, false, 8), 1);
  for (const char* name : {"ppo", "a2c", "dqn", "random", "trpo", "ars", "cma_es"}) {
    INFO(name);
    CHECK(make_algorithm(small(name), discrete.spec())->data_parallel());
  }
  for (const char* name : {"sac", "td3", "ddpg"}) CHECK(make_algorithm(small(name), box.spec())->data_parallel());
}

TEST_CASE("population on ranks: each rank evaluates its slice, every rank gets all returns", "[data_parallel]") {
  // The stand-in's other rank hands back this rank's values, so with 2 ranks and 4 candidates
  // the gathered returns are candidates 0 and 1's twice, and the steps twice this rank's.
  rdsim::VecEnv envs(toy::make_envs(2, true, 8), 3), alone(toy::make_envs(2, true, 8), 3);
  rdsim::Rng init(1);
  rdsim::NetworkConfig linear;
  linear.hidden_sizes = {};
  rdsim::FlatPolicy policy(envs.spec(), linear, false, init, "ars", "test");
  std::vector<Eigen::VectorXf> candidates;
  for (int k = 0; k < 4; ++k) candidates.push_back(Eigen::VectorXf::Constant(policy.size(), 0.1f * static_cast<float>(k - 2)));
  toy::FakeCommunicator comm(2);
  rdsim::RunningNormalizer seen(policy.observation_size()), seen_alone(policy.observation_size());
  const rdsim::PopulationResult r = rdsim::evaluate_population_on_ranks(comm, envs, policy, candidates, 2, nullptr, &seen);
  const rdsim::PopulationResult mine =
      rdsim::evaluate_population(alone, policy, {candidates[0], candidates[1]}, 2, nullptr, &seen_alone);
  REQUIRE(r.returns.size() == 4);
  CHECK(r.returns == std::vector<double>{mine.returns[0], mine.returns[1], mine.returns[0], mine.returns[1]});
  CHECK(r.steps == 2 * mine.steps);
  CHECK(seen.count() == 2 * seen_alone.count());  // both ranks' observations
  CHECK(seen.mean().isApprox(seen_alone.mean()));
  // One rank: the plain population step.
  rdsim::VecEnv one(toy::make_envs(2, true, 8), 3), plain(toy::make_envs(2, true, 8), 3);
  const rdsim::PopulationResult a =
      rdsim::evaluate_population_on_ranks(rdsim::single_process_communicator(), one, policy, candidates, 1, nullptr, nullptr);
  CHECK(a.returns == rdsim::evaluate_population(plain, policy, candidates, 1, nullptr, nullptr).returns);
}
