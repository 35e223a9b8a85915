// `rdsim replay`: runs a saved policy from its model file alone.
#include "rdsim/app/replay.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/app/memory_check.hpp"
#include "rdsim/app/model_file.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/render/png.hpp"

namespace rdsim {
namespace {

// Writes frames of the episodes being replayed as DIR/episode_NNN/frame_NNNN.png.
class FrameRecorder {
public:
  FrameRecorder(std::string dir, Env& env) : dir_(std::move(dir)), env_(env) {}
  bool on() const { return !dir_.empty(); }
  void start_episode(int episode) {
    if (!on()) return;
    char name[32];
    std::snprintf(name, sizeof name, "episode_%03d", episode);
    episode_dir_ = (std::filesystem::path(dir_) / name).string();
    std::error_code ec;
    std::filesystem::create_directories(episode_dir_, ec);
    if (ec) throw Error(episode_dir_ + ": cannot create the folder (" + ec.message() + ")");
    frame_ = 0;
  }
  void capture() {
    if (!on()) return;
    if (!env_.render(image_))
      throw Error("replay --record: env \"" + env_.spec().env_name + "\" cannot draw frames");
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame_++);
    write_png((std::filesystem::path(episode_dir_) / name).string(), image_.width, image_.height, 3,
              image_.rgb.data());
    ++total_;
  }
  long long total() const { return total_; }

private:
  std::string dir_, episode_dir_;
  Env& env_;
  Image image_;
  int frame_ = 0;
  long long total_ = 0;
};

}  // namespace

int replay_command(const ReplayOptions& o) {
  const ModelFile file = read_model_file(o.model_path);
  TrainConfig config = parse_train_config(file.config, o.model_path + " (embedded config)", "replay");
  if (!o.record_dir.empty()) config.env.render_mode = RenderMode::RgbArray;
  config.num_envs = 1;
  check_memory(estimate_training_memory(config, config_spec(config)), memory_limit(o.max_memory_gb), o.model_path);
  auto env = make_env(config.env);
  check_model_spec(file, env->spec(), o.model_path);
  FrameRecorder recorder(o.record_dir, *env);
  auto algo = make_algorithm(config.algorithm, config.seed, env->spec());
  std::istringstream in(file.payload);
  algo->load(in, false, o.model_path);  // a checkpoint's payload starts with the same weights
  if (file.kind == ModelKind::Model && in.peek() != std::char_traits<char>::eof())
    throw Error(o.model_path + ": file is damaged (unexpected trailing data after the weights)");

  const std::uint64_t seed = o.seed.value_or(config.seed);
  Rng rng = Rng::derive(seed, rng_stream::evaluation);
  // Environments without a step limit still end: a policy that never fails stops here.
  const long long step_cap = env->spec().max_episode_steps > 0 ? env->spec().max_episode_steps : 1'000'000;
  double sum_return = 0, sum_length = 0, successes = 0;
  std::printf("%s (%s on %s), %d episode%s, %s actions\n", o.model_path.c_str(), config.algorithm.name().c_str(),
              config.env.name.c_str(), o.episodes, o.episodes == 1 ? "" : "s",
              o.stochastic ? "sampled" : "deterministic");
  for (int k = 0; k < o.episodes; ++k) {
    Observation obs = k == 0 ? env->reset(seed) : env->reset();
    recorder.start_episode(k + 1);
    recorder.capture();
    double ret = 0;
    long long length = 0;
    bool success = false;
    for (bool done = false; !done && length < step_cap;) {
      StepResult r = env->step(algo->act(obs, !o.stochastic, rng));
      ret += r.reward;
      ++length;
      success = success || r.info.success;
      done = r.terminated || r.truncated;
      obs = std::move(r.observation);
      recorder.capture();
    }
    std::printf("episode %d: return %.2f, length %lld, success %s\n", k + 1, ret, length, success ? "yes" : "no");
    sum_return += ret;
    sum_length += static_cast<double>(length);
    successes += success ? 1 : 0;
  }
  std::printf("mean return %.2f, mean length %.1f, success rate %.2f over %d episodes\n", sum_return / o.episodes,
              sum_length / o.episodes, successes / o.episodes, o.episodes);
  if (recorder.on()) std::printf("wrote %lld frames to %s\n", recorder.total(), o.record_dir.c_str());
  return 0;
}

}  // namespace rdsim
