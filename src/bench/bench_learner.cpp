// `rdsim bench-learner`: time per learner update (forward + backward + Adam) of the networks the
// algorithms train (rdsim/bench/bench_learner.hpp).
#include "rdsim/bench/bench_learner.hpp"

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <time.h>
#include <utility>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/bench/bench_run.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/nn.hpp"
#include "rdsim/vecenv/observation_batch.hpp"

namespace rdsim {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kPpoMlpBatch = 512;  // PPO's minibatch of the MLP rows
constexpr int kCnnBatch = 256;
constexpr int kSacBatch = 256;
constexpr float kEntCoef = 0.01f;  // entropy bonus of the PPO rows' loss
constexpr float kLearningRate = 3e-4f;

// One row: a network, its optimiser and fixed inputs; update() is one training step.
struct Workload {
  std::string name;
  nlohmann::json description;  // everything learner.py needs to build the same networks
  std::function<void()> update;
};

// Random inputs and targets, drawn once per row from a fixed seed.
Eigen::MatrixXf uniform(int rows, int cols, float low, float high, Rng& rng) {
  Eigen::MatrixXf m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = low + (high - low) * static_cast<float>(rng.uniform());
  return m;
}

Spec env_spec(bool discrete) {
  EnvConfig config = default_env_config("jaka_button");
  config.is_discrete = discrete;
  return make_env(config)->spec();
}

// PPO's loss over ActorCritic::evaluate() without the ratio clipping: the same network work.
struct PpoLearner {
  std::unique_ptr<ActorCritic> ac;
  std::unique_ptr<nn::Adam> adam;
  Eigen::MatrixXf obs, actions;
  Eigen::VectorXf advantages, returns, d_entropy;

  PpoLearner(const Spec& spec, const NetworkConfig& network, int batch, Rng& rng) {
    ac = std::make_unique<ActorCritic>(spec, network, rng);
    nn::AdamConfig config;
    config.lr = kLearningRate;
    adam = std::make_unique<nn::Adam>(ac->params(), config);
    obs = uniform(ac->observation_size(), batch, spec.observation.type == ObsType::UInt8 ? 0.0f : -1.0f, 1.0f, rng);
    actions.resize(1, batch);
    for (int j = 0; j < batch; ++j) actions(0, j) = static_cast<float>(rng.below(static_cast<std::uint64_t>(spec.action.n)));
    advantages = uniform(batch, 1, -1.0f, 1.0f, rng);
    returns = uniform(batch, 1, -1.0f, 1.0f, rng);
    d_entropy = Eigen::VectorXf::Constant(batch, -kEntCoef / static_cast<float>(batch));
  }

  void update() {
    const float b = static_cast<float>(obs.cols());
    ac->zero_grad();
    const PolicyEval& e = ac->evaluate(obs, actions);
    const Eigen::VectorXf d_log_prob = -advantages / b;
    const Eigen::VectorXf d_value = (e.values - returns) / b;  // of 0.5 mean (v - R)^2
    ac->backward(d_log_prob, d_entropy, d_value);
    adam->step();
  }
};

nlohmann::json mlp_json(int inputs, const std::vector<int>& hidden, int outputs, const std::string& activation) {
  return {{"inputs", inputs}, {"hidden", hidden}, {"outputs", outputs}, {"activation", activation}};
}

Workload ppo_mlp(int width) {
  const Spec spec = env_spec(true);
  NetworkConfig network;
  network.hidden_sizes = {width, width};
  network.activation = "tanh";
  Rng rng(1);
  auto learner = std::make_shared<PpoLearner>(spec, network, kPpoMlpBatch, rng);
  const int obs = learner->ac->observation_size();
  nlohmann::json d = {{"kind", "ppo_mlp"}, {"batch", kPpoMlpBatch}, {"actions", spec.action.n},
                      {"actor", mlp_json(obs, network.hidden_sizes, spec.action.n, "tanh")},
                      {"critic", mlp_json(obs, network.hidden_sizes, 1, "tanh")}, {"ent_coef", kEntCoef}};
  return {"ppo_mlp_" + std::to_string(width), d, [learner] { learner->update(); }};
}

Workload ppo_cnn(const std::string& preset, int side) {
  Spec spec = env_spec(true);
  spec.observation = ObservationSpace{};
  spec.observation.type = ObsType::UInt8;
  spec.observation.shape = {side, side, 3};
  NetworkConfig network;
  network.cnn.preset = preset;
  Rng rng(1);
  auto learner = std::make_shared<PpoLearner>(spec, network, kCnnBatch, rng);
  const nn::CnnShape shape = cnn_shape(network.cnn, spec.observation, 1, "bench-learner");
  nlohmann::json convs = nlohmann::json::array();
  for (const nn::ConvSpec& c : shape.convs) convs.push_back({c.out_channels, c.kernel, c.stride});
  nlohmann::json d = {{"kind", "ppo_cnn"}, {"batch", kCnnBatch}, {"actions", spec.action.n},
                      {"image", {side, side, 3}}, {"convs", convs}, {"fc", shape.hidden_sizes},
                      {"activation", "relu"}, {"ent_coef", kEntCoef}};
  return {"ppo_cnn_" + preset + "_" + std::to_string(side), d, [learner] { learner->update(); }};
}

// SAC's critic step: both Q networks on (observation, action), 0.5 MSE each, one Adam.
struct SacCritics {
  nn::Mlp q[2];
  std::unique_ptr<nn::Adam> adam;
  Eigen::MatrixXf input, target;

  SacCritics(int inputs, const std::vector<int>& hidden, int batch, Rng& rng) {
    for (nn::Mlp& net : q) net = nn::Mlp({inputs, hidden, 1, nn::Activation::ReLU}, 1.0f, rng);
    nn::ParamList params = q[0].params();
    for (const nn::Param& p : q[1].params()) params.push_back(p);
    nn::AdamConfig config;
    config.lr = kLearningRate;
    adam = std::make_unique<nn::Adam>(params, config);
    input = uniform(inputs, batch, -1.0f, 1.0f, rng);
    target = uniform(1, batch, -1.0f, 1.0f, rng);
  }

  void update() {
    const float b = static_cast<float>(input.cols());
    for (nn::Mlp& net : q) net.zero_grad();
    for (nn::Mlp& net : q) {
      const Eigen::MatrixXf d = (net.forward(input) - target) / b;
      net.backward(d, false);
    }
    adam->step();
  }
};

Workload sac_critics() {
  const Spec spec = env_spec(false);
  const int inputs = observation_input_size(spec.observation) + spec.action.dim();
  const std::vector<int> hidden = {256, 256};
  Rng rng(1);
  auto critics = std::make_shared<SacCritics>(inputs, hidden, kSacBatch, rng);
  nlohmann::json d = {{"kind", "sac_critics"}, {"batch", kSacBatch}, {"critic", mlp_json(inputs, hidden, 1, "relu")}};
  return {"sac_critics", d, [critics] { critics->update(); }};
}

// The row makers in table order, so that filtering builds only the rows asked for.
const std::vector<std::pair<std::string, std::function<Workload()>>>& row_makers() {
  static const std::vector<std::pair<std::string, std::function<Workload()>>> makers = {
      {"ppo_mlp_64", [] { return ppo_mlp(64); }},
      {"ppo_mlp_256", [] { return ppo_mlp(256); }},
      {"ppo_mlp_512", [] { return ppo_mlp(512); }},
      {"ppo_cnn_small_64", [] { return ppo_cnn("small", 64); }},
      {"ppo_cnn_small_84", [] { return ppo_cnn("small", 84); }},
      {"ppo_cnn_nature_64", [] { return ppo_cnn("nature", 64); }},
      {"ppo_cnn_nature_84", [] { return ppo_cnn("nature", 84); }},
      {"sac_critics", [] { return sac_critics(); }},
  };
  return makers;
}

bool selected(const std::string& name, const std::vector<std::string>& wanted) {
  if (wanted.empty()) return true;
  for (const std::string& w : wanted)
    if (name.rfind(w, 0) == 0) return true;
  return false;
}

struct Result {
  std::string name;
  nlohmann::json description;
  double ms = 0;      // median wall-clock time per update
  double cpu_ms = 0;  // median CPU time per update, all threads of the process
  long long updates = 0;  // timed updates, all runs
};

// CPU seconds of this process so far, all threads. Unlike wall-clock time it hardly depends on
// other programs sharing the cores (they delay us but do not bill their time to us).
double process_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Wall-clock and CPU seconds per update of one run: updates until min_seconds have passed, at least 3.
std::pair<double, double> timed_run(const Workload& w, double min_seconds, long long& updates) {
  const auto t0 = Clock::now();
  const double cpu0 = process_cpu_seconds();
  long long n = 0;
  double elapsed = 0;
  while (n < 3 || elapsed < min_seconds) {
    w.update();
    ++n;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  updates += n;
  return {elapsed / static_cast<double>(n), (process_cpu_seconds() - cpu0) / static_cast<double>(n)};
}

Result measure(const Workload& w, const BenchLearnerOptions& o) {
  std::fprintf(stderr, "bench-learner: %s ...\n", w.name.c_str());
  for (int i = 0; i < 2; ++i) w.update();  // warm-up: buffers grow, pages fault in
  Result r{w.name, w.description};
  std::vector<double> runs, cpu;
  for (int i = 0; i < o.runs; ++i) {
    const auto [wall, cpu_s] = timed_run(w, o.min_seconds, r.updates);
    runs.push_back(wall);
    cpu.push_back(cpu_s);
  }
  r.ms = 1e3 * median(runs);
  r.cpu_ms = 1e3 * median(cpu);
  return r;
}

std::string shape_text(const nlohmann::json& d) {
  const std::string kind = d["kind"];
  auto hidden = [](const nlohmann::json& mlp) {
    std::string s = "[";
    for (const auto& h : mlp["hidden"]) {
      if (s.size() > 1) s += ',';
      s += std::to_string(h.get<int>());
    }
    return s + "]";
  };
  if (kind == "ppo_mlp") return "actor+critic " + hidden(d["actor"]) + " tanh";
  if (kind == "sac_critics") return "2 x Q " + hidden(d["critic"]) + " relu";
  const auto& image = d["image"];
  return std::to_string(image[0].get<int>()) + "x" + std::to_string(image[1].get<int>()) + "x3, " +
         std::to_string(d["convs"].size()) + " convs + fc " + std::to_string(d["fc"][0].get<int>());
}

void print_table(std::FILE* out, const std::vector<Result>& rows, const BenchLearnerOptions& o) {
  std::fprintf(out, "\nrdsim bench-learner: one update = zero_grad + forward + backward + Adam step, float32;\n"
                    "median of %d runs of >= %.2f s each; matrix products: %s on %d thread%s\n\n",
               o.runs, o.min_seconds, nn::to_string(nn::gemm_backend()), nn::gemm_threads(),
               nn::gemm_threads() == 1 ? "" : "s");
  std::fprintf(out, "%-20s %-34s %6s %12s %12s %14s %12s\n", "row", "networks", "batch", "ms/update", "updates/s",
               "samples/s", "cpu ms/upd");
  for (const Result& r : rows) {
    const int batch = r.description["batch"];
    std::fprintf(out, "%-20s %-34s %6d %12.3f %12.1f %14.0f %12.3f\n", r.name.c_str(),
                 shape_text(r.description).c_str(), batch, r.ms, 1e3 / r.ms, 1e3 * batch / r.ms, r.cpu_ms);
  }
  std::fprintf(out, "\ncpu ms/upd = CPU time of the process per update, all threads: on a busy machine a steadier\n"
                    "figure than the wall-clock ms/update. PyTorch on the same rows, and the ratios: tools/bench/learner.py\n");
}

nlohmann::json to_json(const std::vector<Result>& rows, const BenchLearnerOptions& o) {
  nlohmann::json j = {{"runs", o.runs}, {"min_seconds", o.min_seconds}, {"threads", nn::gemm_threads()},
                      {"gemm", nn::to_string(nn::gemm_backend())},
                      {"cores", std::thread::hardware_concurrency()}, {"optimizer", "adam"},
                      {"learning_rate", kLearningRate}, {"rows", nlohmann::json::array()}};
  for (const Result& r : rows)
    j["rows"].push_back({{"name", r.name}, {"network", r.description}, {"ms_per_update", r.ms},
                         {"cpu_ms_per_update", r.cpu_ms},
                         {"updates", r.updates}});
  return j;
}

}  // namespace

int bench_learner_command(const BenchLearnerOptions& o) {
  if (o.list) {
    for (const auto& [name, make] : row_makers()) std::printf("%s\n", name.c_str());
    return 0;
  }
  if (!o.gemm.empty()) nn::set_gemm_backend(nn::gemm_backend_from_string(o.gemm, "bench-learner: --gemm"));
  else if (nn::onednn_available() && std::getenv("RDSIM_GEMM") == nullptr) nn::set_gemm_backend(nn::GemmBackend::OneDnn);
  if (o.threads > 1 && nn::gemm_backend() != nn::GemmBackend::OneDnn)
    throw Error("bench-learner: --threads " + std::to_string(o.threads) +
                ": only the onednn GEMM runs on several threads (--gemm onednn)");
  nn::set_gemm_threads(o.threads);
  for (const std::string& w : o.rows) {
    bool any = false;
    for (const auto& [name, make] : row_makers()) any = any || selected(name, {w});
    if (!any) throw Error("bench-learner: --row: no row named \"" + w + "\" (rdsim bench-learner --list)");
  }
  std::vector<Result> rows;
  for (const auto& [name, make] : row_makers())
    if (selected(name, o.rows)) rows.push_back(measure(make(), o));
  print_table(table_stream(o.json_path), rows, o);
  write_bench_json(o.json_path, to_json(rows, o));
  return 0;
}

}  // namespace rdsim
