#include <catch2/catch.hpp>
#include <atomic>
#include <cstring>
#include <sys/stat.h>
#include <thread>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_fit.hpp"
#include "rdsim/demos/demo_summary.hpp"
#include "rdsim/demos/demo_writer.hpp"
#include "../finishes_within.hpp"
#include "../scratch_dir.hpp"

using Catch::Matchers::Contains;
using nlohmann::json;
using rdsim::Action;
using rdsim::DemoEpisode;
using rdsim::Observation;
using rdsim::Spec;
using rdsim::StepResult;

namespace {

using Scratch = rdsim::test::ScratchDir;

Spec vector_spec(bool discrete = true) {
  Spec s;
  s.env_name = "toy_reach";
  s.observation.shape = {3};
  s.action.discrete = discrete;
  if (discrete) {
    s.action.n = 4;
  } else {
    s.action.low = Eigen::VectorXf::Constant(2, -1.0f);
    s.action.high = Eigen::VectorXf::Constant(2, 1.0f);
  }
  s.max_episode_steps = 50;
  return s;
}

Spec pixel_spec() {
  Spec s;
  s.env_name = "toy_pixels";
  s.observation.type = rdsim::ObsType::UInt8;
  s.observation.shape = {4, 5, 3};
  s.action.n = 6;
  s.max_episode_steps = 20;
  return s;
}

json env_json(const Spec& s, double step = 0.015) {
  return {{"name", s.env_name}, {"action_step", step}, {"render_mode", "none"}, {"random_target", true}};
}

Observation observation(const Spec& s, int t) {
  Observation o;
  if (s.observation.type == rdsim::ObsType::UInt8) {
    o.pixels.resize(static_cast<size_t>(s.observation.size()));
    for (size_t i = 0; i < o.pixels.size(); ++i) o.pixels[i] = static_cast<std::uint8_t>(i * 7 + static_cast<size_t>(t));
  } else {
    o.values = Eigen::VectorXf::LinSpaced(s.observation.size(), 0.1f * t, 0.1f * t + 1.0f);
  }
  return o;
}

// A well-formed episode of `steps` steps that ends with success when `success`.
DemoEpisode episode(const Spec& s, int steps, bool success, std::uint64_t seed) {
  DemoEpisode e;
  e.source = rdsim::DemoSource::Scripted;
  e.seed = seed;
  e.env_config = env_json(s);
  e.start(observation(s, 0));
  for (int t = 1; t <= steps; ++t) {
    StepResult r;
    r.observation = observation(s, t);
    r.reward = -0.5f / static_cast<float>(t);
    r.info.distance = 0.5f / static_cast<float>(t);
    r.info.success = success && t == steps;
    r.terminated = success && t == steps;
    r.truncated = !success && t == steps;
    const Action a = s.action.discrete ? Action::discrete(t % s.action.n)
                                       : Action::continuous(Eigen::VectorXf::Constant(s.action.dim(), 0.25f * (t % 4) - 0.5f));
    e.add(a, r);
  }
  return e;
}

void write_demos(const std::string& path, const Spec& s, int episodes) {
  rdsim::DemoWriter w(path, env_json(s), s, false);
  for (int k = 0; k < episodes; ++k) w.append(episode(s, 3 + k, k % 2 == 0, 100 + static_cast<std::uint64_t>(k)));
}

// The bytes of a file of `episodes` episodes of `s`.
std::string demo_bytes(const Spec& s, int episodes) {
  Scratch dir("demo_bytes");
  write_demos(dir / "d.demo", s, episodes);
  return rdsim::read_file(dir / "d.demo");
}

void check_same(const DemoEpisode& a, const DemoEpisode& b) {
  REQUIRE(a.steps() == b.steps());
  CHECK(a.source == b.source);
  CHECK(a.seed == b.seed);
  CHECK(a.env_config == b.env_config);
  CHECK(a.terminated == b.terminated);
  CHECK(a.truncated == b.truncated);
  for (size_t t = 0; t < a.observations.size(); ++t) {
    CHECK(a.observations[t].values == b.observations[t].values);
    CHECK(a.observations[t].pixels == b.observations[t].pixels);
  }
  for (size_t t = 0; t < a.actions.size(); ++t) {
    CHECK(a.actions[t].index == b.actions[t].index);
    CHECK(a.actions[t].values == b.actions[t].values);
    CHECK(a.rewards[t] == b.rewards[t]);
    CHECK(a.infos[t].distance == b.infos[t].distance);
    CHECK(a.infos[t].success == b.infos[t].success);
  }
}

}  // namespace

TEST_CASE("demonstration files keep every episode exactly, for vector, pixel and Box envs", "[demos]") {
  Scratch dir("roundtrip");
  for (const Spec& s : {vector_spec(true), vector_spec(false), pixel_spec()}) {
    const std::string path = dir / (s.env_name + (s.action.discrete ? "_d" : "_c") + ".demo");
    std::vector<DemoEpisode> written;
    {
      rdsim::DemoWriter w(path, env_json(s), s, false);
      for (int k = 0; k < 3; ++k) {
        written.push_back(episode(s, 4 + k, k != 1, 7 + static_cast<std::uint64_t>(k)));
        w.append(written.back());
        CHECK(w.episodes() == k + 1);
      }
    }
    const rdsim::DemoFile f = rdsim::read_demo_file(path);
    CHECK(f.env_config == env_json(s));
    CHECK(f.spec.env_name == s.env_name);
    CHECK(f.spec.observation.shape == s.observation.shape);
    CHECK(f.spec.action.discrete == s.action.discrete);
    CHECK(f.interrupted_bytes == 0);
    REQUIRE(f.episodes.size() == 3);
    for (size_t k = 0; k < 3; ++k) check_same(f.episodes[k], written[k]);

    const rdsim::DemoSummary sum = rdsim::summarize(f);
    CHECK(sum.episodes == 3);
    CHECK(sum.steps == 4 + 5 + 6);
    CHECK(sum.success_rate == Approx(2.0 / 3.0));
    CHECK(sum.scripted == 3);
    CHECK(sum.terminated == 2);
    CHECK(sum.truncated == 1);
  }
}

TEST_CASE("a demonstration file grows episode by episode, also across writers", "[demos]") {
  Scratch dir("append");
  const Spec s = vector_spec();
  const std::string path = dir / "a.demo";
  { rdsim::DemoWriter w(path, env_json(s), s, false); }
  CHECK(rdsim::read_demo_file(path).episodes.empty());  // a fresh file is readable at once
  for (int k = 0; k < 3; ++k) {
    rdsim::DemoWriter w(path, env_json(s), s, true);
    CHECK(w.episodes() == k);
    w.append(episode(s, 2, true, 1));
    CHECK(rdsim::read_demo_file(path).episodes.size() == static_cast<size_t>(k + 1));  // on disk at once
  }
  CHECK_THROWS_WITH(rdsim::DemoWriter(path, env_json(s), s, false), Contains("already exists"));
  // Another env cannot be appended to it.
  const Spec other = vector_spec(false);
  CHECK_THROWS_WITH(rdsim::DemoWriter(path, env_json(s), other, true), Contains("Box(2)"));
}

TEST_CASE("a crash while an episode is written loses that episode only", "[demos]") {
  Scratch dir("crash");
  const Spec s = vector_spec();
  const std::string path = dir / "c.demo";
  write_demos(path, s, 2);
  // What a crash between writing a record and committing it leaves: the record's bytes (here half
  // of them) after the committed data.
  const std::string record = rdsim::encode_demo_episode(episode(s, 9, true, 5), s, "test");
  {
    std::ofstream out(path, std::ios::binary | std::ios::app);
    out << record.substr(0, record.size() / 2);
  }
  rdsim::DemoFile f = rdsim::read_demo_file(path);
  CHECK(f.episodes.size() == 2);
  CHECK(f.interrupted_bytes == record.size() / 2);
  // The next writer cuts the tail off and carries on.
  {
    rdsim::DemoWriter w(path, env_json(s), s, true);
    w.append(episode(s, 4, false, 6));
  }
  f = rdsim::read_demo_file(path);
  CHECK(f.episodes.size() == 3);
  CHECK(f.interrupted_bytes == 0);
  CHECK(f.episodes[2].steps() == 4);
}

TEST_CASE("a truncated demonstration file is one clear error, wherever it is cut", "[demos][bad-file]") {
  const std::string bytes = demo_bytes(vector_spec(), 3);
  for (size_t keep = 0; keep < bytes.size(); keep += (keep < 64 ? 1 : 7)) {
    INFO("kept " << keep << " of " << bytes.size() << " bytes");
    const std::string cut = bytes.substr(0, keep);
    REQUIRE_THROWS_AS(rdsim::decode_demo_file(cut, "t.demo"), rdsim::Error);
    try {
      rdsim::decode_demo_file(cut, "t.demo");
    } catch (const rdsim::Error& e) {
      const std::string what = e.what();
      CHECK((what.find("truncated") != std::string::npos || what.find("not an rdsim demonstration file") != std::string::npos));
    }
  }
}

TEST_CASE("every flipped bit in a demonstration file is detected", "[demos][bad-file]") {
  const std::string bytes = demo_bytes(vector_spec(), 2);
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::string damaged = bytes;
    damaged[i] = static_cast<char>(damaged[i] ^ (1 << (i % 8)));
    INFO("byte " << i << " of " << bytes.size());
    CHECK_THROWS_AS(rdsim::decode_demo_file(damaged, "f.demo"), rdsim::Error);
  }
  std::string last = bytes;
  last[bytes.size() - 12] ^= 0x10;  // in the last record's flags
  CHECK_THROWS_WITH(rdsim::decode_demo_file(last, "f.demo"), Contains("f.demo: episode 2: file is damaged (checksum mismatch)"));
}

TEST_CASE("demonstrations of another env or another action space do not fit", "[demos][bad-file]") {
  Scratch dir("fit");
  const Spec s = vector_spec();
  const std::string path = dir / "d.demo";
  write_demos(path, s, 1);
  const rdsim::DemoFile f = rdsim::read_demo_file(path);
  CHECK_NOTHROW(rdsim::check_demos_fit(f, env_json(s), s));
  // Drawing options and the episode distribution do not matter.
  json drawn = env_json(s);
  drawn["render_mode"] = "rgb_array";
  drawn["random_target"] = false;
  CHECK_NOTHROW(rdsim::check_demos_fit(f, drawn, s));

  Spec other_env = s;
  other_env.env_name = "jaka_button";
  CHECK_THROWS_WITH(rdsim::check_demos_fit(f, env_json(other_env), other_env),
                    Contains("d.demo: these demonstrations do not fit the env: recorded on env toy_reach, this env is jaka_button"));
  const Spec box = vector_spec(false);
  CHECK_THROWS_WITH(rdsim::check_demos_fit(f, env_json(box), box),
                    Contains("actions are Discrete(4), env toy_reach has Box(2) (env.is_discrete differs)"));
  Spec more_actions = s;
  more_actions.action.n = 6;
  CHECK_THROWS_WITH(rdsim::check_demos_fit(f, env_json(more_actions), more_actions), Contains("Discrete(6)"));
  Spec pixels = pixel_spec();
  pixels.env_name = s.env_name;
  CHECK_THROWS_WITH(rdsim::check_demos_fit(f, env_json(pixels), pixels), Contains("observations are Float32[3]"));
  CHECK_THROWS_WITH(rdsim::check_demos_fit(f, env_json(s, 0.02), s),
                    Contains("env.action_step is 0.015 in the demonstrations, 0.02 here"));
}

TEST_CASE("bad episodes are refused before they reach the file", "[demos][bad-file]") {
  Scratch dir("refuse");
  const Spec s = vector_spec();
  const std::string path = dir / "r.demo";
  rdsim::DemoWriter w(path, env_json(s), s, false);
  DemoEpisode e = episode(s, 3, true, 1);
  e.actions[1].index = 4;
  CHECK_THROWS_WITH(w.append(e), Contains("action 1 is outside the action space Discrete(4)"));
  e = episode(s, 3, true, 1);
  e.observations[2].values[0] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(w.append(e), Contains("observation 2 is not a finite Float32[3] observation"));
  e = episode(s, 3, true, 1);
  e.observations.pop_back();
  CHECK_THROWS_WITH(w.append(e), Contains("expected 4 observations"));
  DemoEpisode empty;
  empty.start(observation(s, 0));
  CHECK_THROWS_WITH(w.append(empty), Contains("at least one step"));
  CHECK(rdsim::read_demo_file(path).episodes.empty());

  const Spec box = vector_spec(false);
  rdsim::DemoWriter wb(dir / "b.demo", env_json(box), box, false);
  DemoEpisode eb = episode(box, 2, true, 1);
  eb.actions[0].values[1] = 1.5f;
  CHECK_THROWS_WITH(wb.append(eb), Contains("outside the action space Box(2)"));
}

TEST_CASE("foreign files and other versions are named as such", "[demos][bad-file]") {
  Scratch dir("foreign");
  CHECK_THROWS_WITH(rdsim::decode_demo_file("RDSIMMDL and more bytes than a header needs..............", "m.bin"),
                    Contains("m.bin: not an rdsim demonstration file"));
  CHECK_THROWS_WITH(rdsim::decode_demo_file("", "e.demo"), Contains("not an rdsim demonstration file"));
  CHECK_THROWS_WITH(rdsim::read_demo_file(dir / "missing.demo"), Contains("missing.demo: cannot open"));
  // A file of a future format version (with a valid commit checksum) is refused by version.
  const Spec s = vector_spec();
  std::string bytes = rdsim::encode_demo_file(env_json(s), s);
  bytes[8] = 2;
  std::string prefix = bytes.substr(0, 32);
  const std::uint64_t sum = rdsim::fnv1a64(prefix);
  std::memcpy(bytes.data() + 32, &sum, 8);
  CHECK_THROWS_WITH(rdsim::decode_demo_file(bytes, "v2.demo"),
                    Contains("v2.demo: demonstration format version 2 is not supported"));
}

TEST_CASE("a missing demonstration file names the command that records it", "[demos]") {
  CHECK_THROWS_WITH(rdsim::read_demo_file("demos/none_here.demo"),
                    Contains("demos/none_here.demo: cannot open: No such file or directory; make it with: rdsim demos "
                             "record --config TRAINING_CONFIG.json --out demos/none_here.demo"));
}

TEST_CASE("one writer at a time: a second writer of the same demonstration file is refused", "[demos][lock]") {
  Scratch dir("demo_lock");
  const Spec s = vector_spec();
  const std::string path = dir / "c.demo";
  write_demos(path, s, 1);
  {
    rdsim::DemoWriter first(path, env_json(s), s, true);
    // Before: the second writer read the file, both appended at the same offset and the file was
    // damaged, the episode that was there before included.
    CHECK_THROWS_WITH(rdsim::DemoWriter(path, env_json(s), s, true),
                      Contains(path) && Contains("another rdsim process is recording to this demonstration file"));
    first.append(episode(s, 3, true, 7));
  }
  rdsim::DemoWriter next(path, env_json(s), s, true);  // the lock goes with its writer
  next.append(episode(s, 2, false, 8));
  CHECK(rdsim::read_demo_file(path).episodes.size() == 3);
}

TEST_CASE("two writers creating the same new demonstration file at once: one wins, the file stays whole",
          "[demos][lock]") {
  Scratch dir("demo_race");
  const Spec s = vector_spec();
  for (int trial = 0; trial < 20; ++trial) {
    std::string name = "r";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "r" + std::to_string
    name += std::to_string(trial);
    const std::string path = dir / (name + ".demo");
    std::atomic<int> ready{0}, wrote{0};
    auto writer = [&](std::uint64_t seed, bool append) {
      ++ready;
      while (ready.load() < 2) {
      }
      try {
        rdsim::DemoWriter w(path, env_json(s), s, append);
        for (int k = 0; k < 3; ++k) w.append(episode(s, 2 + k, true, seed + static_cast<std::uint64_t>(k)));
        wrote += 3;
      } catch (const rdsim::Error& e) {
        const std::string m = e.what();
        CHECK((m.find("another rdsim process") != std::string::npos || m.find("already exists") != std::string::npos));
      }
    };
    const bool append = trial % 2 == 0;
    std::thread a(writer, 100, append), b(writer, 200, append);
    a.join();
    b.join();
    // Every episode a writer reported written is in the file, and the file reads back whole.
    const rdsim::DemoFile f = rdsim::read_demo_file(path);
    CHECK(static_cast<int>(f.episodes.size()) == wrote.load());
    CHECK(wrote.load() >= 3);
  }
  for (const auto& e : std::filesystem::directory_iterator(dir.path))
    CHECK(e.path().extension() == ".demo");  // no temporaries left behind
}

TEST_CASE("special files are refused at once, and the header is checked before the body is read", "[demos][bad-file]") {
  Scratch dir("demo_special");
  const Spec s = vector_spec();
  const std::string fifo = dir / "x.fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  using namespace std::chrono_literals;
  // Before: opening the FIFO waited for a writer forever.
  auto r = rdsim::test::finishes_within(5s, [&] { rdsim::read_demo_file(fifo); });
  CHECK(r.in_time);
  CHECK(r.threw);
  CHECK_THAT(r.message, Contains(fifo) && Contains("is not a regular file (it is a FIFO)"));
  r = rdsim::test::finishes_within(5s, [&] { rdsim::DemoWriter(fifo, env_json(s), s, true); });
  CHECK(r.in_time);
  CHECK_THAT(r.message, Contains("is not a regular file (it is a FIFO)"));
  // Before: /dev/urandom was read on and on (gigabytes of memory) before its magic was checked.
  r = rdsim::test::finishes_within(5s, [&] { rdsim::read_demo_file("/dev/urandom"); });
  CHECK(r.in_time);
  CHECK_THAT(r.message, Contains("/dev/urandom") && Contains("is not a regular file (it is a character device)"));
  // A large regular file that is not a demonstration file: refused after its first 40 bytes.
  const std::string big = dir / "big.demo";
  {
    std::ofstream out(big, std::ios::binary);
    out << "NOTADEMO";
  }
  std::filesystem::resize_file(big, 8ull << 30);  // sparse: no disk used
  r = rdsim::test::finishes_within(5s, [&] { rdsim::read_demo_file(big); });
  CHECK(r.in_time);
  CHECK_THAT(r.message, Contains("not an rdsim demonstration file"));
}
