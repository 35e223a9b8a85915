// VecEnv's observation batch for a space with both parts: a UInt8 image and Float32 values beside
// it (a goal env's raw pixels), stepped on threads and in worker processes, with the final
// observations of ended episodes and a checkpoint round trip.
#include <catch2/catch.hpp>

#include <sstream>

#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"

namespace {

using namespace rdsim;

// A 4x3 RGB image whose bytes and two values follow a seeded counter; episodes of 5 steps.
class ImageAndValuesEnv final : public Env {
public:
  ImageAndValuesEnv() {
    spec_.env_name = "image_and_values";
    spec_.observation.type = ObsType::UInt8;
    spec_.observation.shape = {3, 4, 3};
    spec_.observation.vector_size = 2;
    spec_.observation.low = Eigen::VectorXf::Constant(2, -1e6f);
    spec_.observation.high = Eigen::VectorXf::Constant(2, 1e6f);
    spec_.action.discrete = true;
    spec_.action.n = 2;
    spec_.max_episode_steps = 5;
  }
  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed) override {
    if (seed) rng_.reseed(*seed);
    start_ = static_cast<int>(rng_.below(100));
    t_ = 0;
    return observe();
  }
  StepResult step(const Action& action) override {
    t_ += 1 + action.index;
    StepResult r;
    r.reward = static_cast<float>(t_);
    r.truncated = t_ >= spec_.max_episode_steps;
    r.observation = observe();
    return r;
  }

private:
  Observation observe() const {
    Observation o = make_observation(spec_.observation);
    for (size_t i = 0; i < o.pixels.size(); ++i) o.pixels[i] = static_cast<std::uint8_t>(start_ + t_ * 7 + static_cast<int>(i));
    o.values << static_cast<float>(start_), static_cast<float>(t_) + 0.5f;
    return o;
  }
  Spec spec_;
  Rng rng_{0};
  int start_ = 0, t_ = 0;
};

struct Trace {
  std::vector<std::uint8_t> pixels;
  std::vector<float> values, finals;
};

Trace run(int threads, EnvWorkers workers) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < 3; ++i) envs.push_back(std::make_unique<ImageAndValuesEnv>());
  VecEnv vec(std::move(envs), 5, 20, threads, workers);
  Trace trace;
  std::vector<Action> actions(3);
  for (int t = 0; t < 12; ++t) {
    for (int i = 0; i < 3; ++i) actions[static_cast<size_t>(i)] = Action::discrete((t + i) % 2);
    const auto& steps = vec.step(actions);
    const ObservationBatch& b = vec.observations();
    REQUIRE(b.pixels.rows() == 36);
    REQUIRE(b.values.rows() == 2);
    trace.pixels.insert(trace.pixels.end(), b.pixels.data(), b.pixels.data() + b.pixels.size());
    trace.values.insert(trace.values.end(), b.values.data(), b.values.data() + b.values.size());
    for (const EnvStep& s : steps)
      if (s.done()) {
        REQUIRE(s.final_observation.pixels.size() == 36u);
        REQUIRE(s.final_observation.values.size() == 2);
        trace.finals.push_back(s.final_observation.values[1]);
        trace.finals.push_back(static_cast<float>(s.final_observation.pixels[35]));
      }
  }
  // The network input: the image's bytes scaled to [0, 1], then the values.
  Eigen::MatrixXf scratch;
  const Eigen::MatrixXf& input = network_input(vec.observations(), scratch);
  REQUIRE(input.rows() == 38);
  CHECK(input(35, 1) == static_cast<float>(vec.observations().pixels(35, 1)) * pixel_input_scale);
  CHECK(input(37, 1) == vec.observations().values(1, 1));
  return trace;
}

}  // namespace

TEST_CASE("VecEnv: an image with values beside it, on threads and in worker processes alike", "[vec_env][observations]") {
  const Trace one = run(1, EnvWorkers::threads);
  CHECK_FALSE(one.finals.empty());
  for (const auto& [threads, workers] : {std::pair{2, EnvWorkers::threads}, std::pair{2, EnvWorkers::processes},
                                         std::pair{3, EnvWorkers::processes}}) {
    const Trace other = run(threads, workers);
    CHECK(other.pixels == one.pixels);
    CHECK(other.values == one.values);
    CHECK(other.finals == one.finals);
  }
}

TEST_CASE("ObservationBatch: assign and copy_to keep both parts, and a wrong size is an error", "[vec_env][observations]") {
  ObservationSpace space;
  space.type = ObsType::UInt8;
  space.shape = {2, 2, 1};
  space.vector_size = 3;
  ObservationBatch batch;
  batch.resize(space, 2);
  Observation o = make_observation(space);
  o.pixels = {1, 2, 3, 4};
  o.values << 0.5f, -1.0f, 2.0f;
  batch.assign(1, o);
  Observation back;
  batch.copy_to(1, back);
  CHECK(back.pixels == o.pixels);
  CHECK(back.values == o.values);
  o.values.resize(2);
  CHECK_THROWS(batch.assign(0, o));
}
