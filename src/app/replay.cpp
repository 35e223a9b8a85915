// `rdsim replay`: runs a saved policy from its model file alone.
#include "rdsim/app/replay.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/app/env_source.hpp"
#include "rdsim/app/memory_check.hpp"
#include "rdsim/app/model_file.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/render/png.hpp"
#include "rdsim/video/overlay.hpp"
#include "rdsim/video/video_writer.hpp"

namespace rdsim {
namespace {

// Writes frames of the episodes being replayed as DIR/episode_NNN/frame_NNNN.png.
class FrameRecorder {
public:
  explicit FrameRecorder(std::string dir) : dir_(std::move(dir)) {}
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
  void save(const Image& image) {
    if (!on()) return;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame_++);
    write_png((std::filesystem::path(episode_dir_) / name).string(), image.width, image.height, 3, image.rgb.data());
    ++total_;
  }
  long long total() const { return total_; }

private:
  std::string dir_, episode_dir_;
  int frame_ = 0;
  long long total_ = 0;
};

// What a replay shows of each step: the env's frame, to PNG files and/or a captioned video.
class FrameCapture {
public:
  FrameCapture(const ReplayOptions& o, Env& env, int episodes, int width, int height)
      : env_(env), recorder_(o.record_dir), every_(o.frame_every), fps_(o.video_fps), episodes_(episodes) {
    if (!o.video_path.empty()) video_ = open_video(o.video_path, width, height, o.video_fps);
  }
  bool on() const { return recorder_.on() || video_; }
  void start_episode(int episode) {
    recorder_.start_episode(episode);
    episode_ = episode;
  }
  // The state after `step` steps (0: the reset); the last step of an episode is always kept.
  void capture(long long step, double episode_return, bool success, bool last) {
    if (!on() || (step % every_ != 0 && !last)) return;
    if (!env_.render(frame_)) {
      throw Error("replay: env \"" + env_.spec().env_name + "\" cannot draw frames (--record, --video)");
    }
    recorder_.save(frame_);
    if (!video_) return;
    char line[3][64];
    std::snprintf(line[0], sizeof line[0], "episode %d/%d  step %lld", episode_, episodes_, step);
    std::snprintf(line[1], sizeof line[1], "return %.2f", episode_return);
    std::snprintf(line[2], sizeof line[2], "success: %s", success ? "yes" : "no");
    draw_overlay(frame_, {{line[0]}, {line[1]}, {line[2], success}});
    // An episode's last frame stays half a second, so its outcome can be read.
    for (int k = 0, n = last ? std::max(1, fps_ / 2) : 1; k < n; ++k) video_->add_frame(frame_);
  }
  void close() {
    if (video_) video_->close();
  }
  long long pictures() const { return recorder_.total(); }
  std::string video_format() const { return video_ ? video_->format() : ""; }

private:
  Env& env_;
  FrameRecorder recorder_;
  std::unique_ptr<VideoWriter> video_;
  Image frame_;
  int every_, fps_, episodes_, episode_ = 0;
};

}  // namespace

int replay_command(const ReplayOptions& o) {
  const ModelFile file = read_model_file(o.model_path);
  TrainConfig config = parse_train_config(file.config, o.model_path + " (embedded config)", "replay");
  if (!o.record_dir.empty() || !o.video_path.empty()) config.env.render_mode = RenderMode::RgbArray;
  if (o.frame_width > 0) config.env.render_width = o.frame_width;
  if (o.frame_height > 0) config.env.render_height = o.frame_height;
  config.num_envs = 1;
  check_memory(estimate_training_memory(config, config_spec(config)), memory_limit(o.max_memory_gb), o.model_path);
  auto env = open_env(config.env, config.remote);
  check_model_spec(file, env->spec(), o.model_path);
  FrameCapture frames(o, *env, o.episodes, config.env.render_width, config.env.render_height);
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
    frames.start_episode(k + 1);
    frames.capture(0, 0.0, false, false);
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
      frames.capture(length, ret, success, done || length >= step_cap);
    }
    std::printf("episode %d: return %.2f, length %lld, success %s\n", k + 1, ret, length, success ? "yes" : "no");
    sum_return += ret;
    sum_length += static_cast<double>(length);
    successes += success ? 1 : 0;
  }
  std::printf("mean return %.2f, mean length %.1f, success rate %.2f over %d episodes\n", sum_return / o.episodes,
              sum_length / o.episodes, successes / o.episodes, o.episodes);
  frames.close();
  if (!o.record_dir.empty()) std::printf("wrote %lld frames to %s\n", frames.pictures(), o.record_dir.c_str());
  if (!o.video_path.empty()) std::printf("wrote %s (%s)\n", o.video_path.c_str(), frames.video_format().c_str());
  return 0;
}

}  // namespace rdsim
