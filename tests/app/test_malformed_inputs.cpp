// The malformed-input corpus (tests/malformed/, written by tools/gen_malformed_corpus.py) and
// damaged model and checkpoint files made here from a model the test trains, run against the
// real binary as a user would, each under a 1 GiB address-space limit (ulimit -v) and a time
// limit. Every case must end with exit status 1 and ONE line "rdsim: error: ..." naming the
// file/key/option: no crash, no hang, no "internal error", no out-of-memory, no silent acceptance.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "process_util.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/core/checksum.hpp"
#include "rl_test_util.hpp"

namespace fs = std::filesystem;

namespace {

constexpr unsigned long long kAddressSpace = 1ull << 30;  // 1 GiB, as `ulimit -v 1048576`

// The training runs' arguments after the config. Under AddressSanitizer there is no address-space
// limit (proctest::kAddressSanitizer), so the memory check gets the limit the 1 GiB would give it.
std::vector<std::string> train_args(const std::string& config, const std::string& log_dir) {
  std::vector<std::string> args{"train", "--quiet", "--config", config, "--log-dir", log_dir};
  if (proctest::kAddressSanitizer) args.insert(args.end(), {"--max-memory", "0.8"});
  return args;
}

std::string source_root() {
  const char* root = std::getenv("RDSIM_ROOT");
  return root && *root ? root : RDSIM_SOURCE_DIR;
}

struct Case {
  std::string kind, input, target, expected;
};

std::vector<Case> read_manifest() {
  std::ifstream in(source_root() + "/tests/malformed/cases.tsv");
  std::vector<Case> cases;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string field; std::getline(ss, field, '\t');) f.push_back(field);
    if (f.size() == 4) cases.push_back({f[0], f[1], f[2], f[3]});
  }
  return cases;
}

// Runs one case and checks everything the corpus promises; `names` must appear in the message.
struct Checker {
  const rltest::ScratchDir& dir;
  int count = 0, failures = 0;
  std::string report;  // one paragraph per failed case

  void expect_error(const std::string& label, const std::vector<std::string>& args, const std::vector<std::string>& names,
                    const std::string& run_dir = "") {
    ++count;
    const proctest::Outcome o = proctest::run(args, dir.path.string(), kAddressSpace, std::chrono::seconds(60));
    const std::vector<std::string> lines = rltest::lines(o.err);
    std::string why;
    if (o.timed_out) why = "hang (killed after 60 s)";
    else if (o.signal) why = "crashed with signal " + std::to_string(o.signal);
    else if (o.exit_code == 0) why = "accepted silently (exit 0)";
    else if (o.exit_code != 1) why = "exit status " + std::to_string(o.exit_code) + ", expected 1";
    else if (lines.size() != 1) why = std::to_string(lines.size()) + " lines on stderr, expected 1";
    else if (lines[0].rfind("rdsim: error: ", 0) != 0) why = "the line does not start with \"rdsim: error: \"";
    else if (o.err.find("internal error") != std::string::npos) why = "internal error";
    else if (o.err.find("out of memory") != std::string::npos) why = "ran out of memory under the 1 GiB limit";
    for (const auto& n : names)
      if (why.empty() && o.err.find(n) == std::string::npos) why = "the message does not name \"" + n + "\"";
    if (why.empty() && !run_dir.empty() && fs::exists(fs::path(run_dir) / "model.bin")) why = "a run folder was written";
    if (!why.empty()) {
      ++failures;
      report += label + ": " + why + "\n  stderr: " + o.err.substr(0, 600) + "\n";
    }
  }
};

// --- model and checkpoint files: raw bytes with a correct checksum -----------------------------

void put_u32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
void put_u64(std::string& s, std::uint64_t v) { s.append(reinterpret_cast<const char*>(&v), 8); }

// A model file from its parts, with the checksum it needs, so only the contents are wrong.
std::string raw_model(std::uint32_t version, std::uint32_t kind, const std::string& config, const std::string& spec,
                      const std::string& payload, const std::string& policy = "") {
  std::string out = "RDSIMMDL";
  put_u32(out, version);
  put_u32(out, kind);
  put_u64(out, config.size());
  out += config;
  if (version >= 3) {
    put_u64(out, spec.size());
    out += spec;
  }
  put_u64(out, payload.size());
  out += payload;
  if (version >= 4) {
    put_u64(out, policy.size());
    out += policy;
  }
  put_u64(out, rdsim::fnv1a64(out));
  return out;
}

template <class T>
std::string with_value(std::string bytes, std::size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
  return bytes;
}

// Offsets of the fields in a PPO checkpoint payload of cartpole (formats: nn/serialize, Adam,
// OnPolicy::save, train.cpp's trainer state, VecEnv::save, EpisodeTracker::save).
struct CheckpointLayout {
  std::size_t first_weight = 0, tensor_rows = 0, adam_t = 0, adam_lr = 0, adam_first_moment = 0, rng = 0, updates = 0,
              progress_rows = 0, episode_rows = 0, timesteps = 0, wall = 0, stateful = 0, env_state = 0, cart_x = 0,
              observation_count = 0, observation = 0, episodes = 0;
};

CheckpointLayout walk(const std::string& p) {
  CheckpointLayout l;
  std::size_t at = 0;
  auto u32 = [&] { std::uint32_t v; std::memcpy(&v, p.data() + at, 4); at += 4; return v; };
  auto u64 = [&] { std::uint64_t v; std::memcpy(&v, p.data() + at, 8); at += 8; return v; };
  auto tensors = [&](std::uint32_t n, std::size_t* first) {
    for (std::uint32_t i = 0; i < n; ++i) {
      if (i == 0 && first == &l.first_weight) l.tensor_rows = at;
      const std::uint64_t r = u32(), c = u32();
      if (i == 0 && first) *first = at;
      at += 4 * r * c;
    }
  };
  at += 8;  // "RDNP", version
  const std::uint32_t count = u32();
  tensors(count, &l.first_weight);
  at += 8;  // Adam tag, count
  l.adam_t = at;
  at += 8;
  l.adam_lr = at;
  at += 4;
  tensors(2 * count, &l.adam_first_moment);
  l.rng = at;
  for (int rng = 0; rng < 2; ++rng) {  // sample and shuffle generators: u64 length + bytes
    const std::uint64_t n = u64();
    at += n;
  }
  l.updates = at;
  at += 8;
  l.progress_rows = at;
  l.episode_rows = at + 8;
  at += 24;
  l.timesteps = at;
  l.wall = at + 8;
  l.stateful = at + 16;
  at += 20;
  l.env_state = at;
  const std::uint64_t state_size = u64();
  l.cart_x = at;
  at += state_size;
  l.observation_count = at;
  at += 8;
  l.observation = at;
  return l;
}

}  // namespace

TEST_CASE("malformed inputs: the corpus (configs, URDFs, meshes, command lines) gets one clear error each", "[malformed]") {
  rltest::ScratchDir dir("malformed_corpus");
  const std::string corpus = source_root() + "/tests/malformed";
  const std::vector<Case> cases = read_manifest();
  REQUIRE(cases.size() >= 250);
  // A config file just over the 16 MiB limit, made here rather than stored.
  const std::string big = dir / "big.json";
  {
    std::ofstream out(big);
    out << std::string(16 * 1024 * 1024, ' ') << "{}";
  }
  Checker check{dir, 0, 0, {}};
  int n = 0;
  for (const Case& c : cases) {
    const std::string run = dir / ("run" + std::to_string(n++));
    if (c.kind == "config") {
      const std::string file = corpus + "/" + c.input;
      check.expect_error(c.input, train_args(file, run), {file, c.expected}, run);
    } else if (c.kind == "urdf") {
      const fs::path assets = fs::path(run) / "assets";
      fs::create_directories(assets);
      fs::copy(source_root() + "/assets", assets, fs::copy_options::recursive);
      const std::string target = (assets / c.target).string();
      fs::copy_file(corpus + "/" + c.input, target, fs::copy_options::overwrite_existing);
      const std::string config = run + "/config_in.json";
      rltest::spit(config, R"({"env": {"name": "jaka_button", "urdf_root": ")" + assets.string() +
                               R"("}, "total_timesteps": 256, "network": {"hidden_sizes": [8]}, "ppo": {"n_steps": 64, "batch_size": 64}})");
      check.expect_error(c.input, train_args(config, run + "/out"), {target, c.expected}, run + "/out");
    } else if (c.kind == "mesh") {
      // The mesh goes to TARGET (jaka/mesh.EXT); the Jaka URDF showing it on its base link replaces jaka_zu7.urdf.
      const fs::path assets = fs::path(run) / "assets";
      fs::create_directories(assets);
      fs::copy(source_root() + "/assets", assets, fs::copy_options::recursive);
      const std::string mesh = (assets / c.target).string();
      fs::copy_file(corpus + "/" + c.input, mesh, fs::copy_options::overwrite_existing);
      const std::string urdf = (assets / "jaka/jaka_zu7.urdf").string();
      fs::copy_file(corpus + "/urdfs/jaka-mesh-" + fs::path(c.target).extension().string().substr(1) + ".urdf", urdf,
                    fs::copy_options::overwrite_existing);
      const std::string config = run + "/config_in.json";
      rltest::spit(config, R"({"env": {"name": "jaka_button", "urdf_root": ")" + assets.string() +
                               R"("}, "total_timesteps": 256, "network": {"hidden_sizes": [8]}, "ppo": {"n_steps": 64, "batch_size": 64}})");
      const std::string uri = "mesh \"" + fs::path(c.target).filename().string() + "\": ";
      check.expect_error(c.input, train_args(config, run + "/out"), {urdf, "link \"", uri, c.expected}, run + "/out");
    } else if (c.kind == "cli") {
      std::string line = c.target;
      for (const auto& [key, value] : std::map<std::string, std::string>{{"{tmp}", dir.path.string()}, {"{big}", big}, {"{root}", source_root()}})
        for (std::size_t at; (at = line.find(key)) != std::string::npos;) line.replace(at, key.size(), value);
      check.expect_error("cli: " + c.target, proctest::split_args(line), {c.expected});
    }
  }
  INFO(check.count << " cases, " << check.failures << " failed\n" << check.report);
  CHECK(check.failures == 0);
}

TEST_CASE("malformed inputs: damaged, edited and foreign model and checkpoint files", "[malformed]") {
  rltest::ScratchDir dir("malformed_models");
  // A tiny run: its model.bin and checkpoint.bin are the originals the cases damage.
  const std::string config = dir / "tiny.json";
  rltest::spit(config, R"({"env": {"name": "cartpole"}, "seed": 5, "total_timesteps": 256, "num_envs": 2,
    "network": {"hidden_sizes": [8]}, "ppo": {"n_steps": 32, "batch_size": 32, "n_epochs": 1}})");
  const auto trained = proctest::run({"train", "--quiet", "--config", config, "--log-dir", dir / "run"}, dir.path.string());
  REQUIRE(trained.exit_code == 0);
  const rdsim::ModelFile model = rdsim::read_model_file(dir / "run/model.bin");
  const rdsim::ModelFile ckpt = rdsim::read_model_file(dir / "run/checkpoint.bin");
  const std::string cfg = model.config.dump();
  const std::string spec = model.spec;
  REQUIRE_FALSE(spec.empty());
  Checker check{dir, 0, 0, {}};

  // --- model.bin cases: `rdsim replay FILE`
  std::vector<std::pair<std::string, std::string>> models;  // (bytes, expected)
  // Today's files (version 4) hold the policy part too; the cases below write version 3 files
  // (which this rdsim still reads) unless they are about the envelope.
  const std::string good = raw_model(4, 0, cfg, spec, model.payload, model.policy);
  REQUIRE(good == rltest::slurp(dir / "run/model.bin"));
  for (std::size_t cut : {std::size_t{0}, std::size_t{4}, std::size_t{8}, std::size_t{12}, std::size_t{20}, good.size() / 3,
                          good.size() / 2, good.size() - 9, good.size() - 1})
    models.push_back({good.substr(0, cut), cut < 8 ? "not an rdsim model file" : "truncated"});
  for (std::size_t at : {std::size_t{9}, std::size_t{14}, std::size_t{30}, good.size() / 2, good.size() - 20, good.size() - 3}) {
    std::string d = good;
    d[at] = static_cast<char>(d[at] ^ 0x41);
    models.push_back({d, "model.bin_"});  // any clear message naming the file
  }
  models.push_back({good + "x", "damaged"});
  models.push_back({"PK\x03\x04 zip", "not an rdsim model file"});
  models.push_back({std::string(4096, '\0'), "not an rdsim model file"});
  for (std::uint32_t v : {0u, 5u, 99u, 0xffffffffu}) models.push_back({raw_model(v, 0, cfg, spec, model.payload), "version"});
  models.push_back({raw_model(3, 7, cfg, spec, model.payload), "unknown kind 7"});
  // Header sizes larger than the file: refused before anything that size is allocated.
  for (std::uint64_t size : {std::uint64_t{1} << 40, std::numeric_limits<std::uint64_t>::max(), std::uint64_t{1} << 62}) {
    std::string d = good;
    std::memcpy(d.data() + 16, &size, 8);
    models.push_back({d, "truncated"});
  }
  // Embedded config: not JSON, nested, duplicate keys, invalid values, another env.
  models.push_back({raw_model(3, 0, "{not json", spec, model.payload), "not valid JSON"});
  models.push_back({raw_model(3, 0, "", spec, model.payload), "not valid JSON"});
  models.push_back({raw_model(3, 0, "[1, 2]", spec, model.payload), "not a JSON object"});
  models.push_back({raw_model(3, 0, std::string(50000, '[') + std::string(50000, ']'), spec, model.payload), "nested more than 64"});
  models.push_back({raw_model(3, 0, cfg.substr(0, cfg.size() - 1) + R"(,"seed":1})", spec, model.payload), "seed: duplicate key"});
  auto edited = [&](const std::string& path, const nlohmann::json& value) {
    nlohmann::json j = model.config;
    j[nlohmann::json::json_pointer(path)] = value;
    return j.dump();
  };
  models.push_back({raw_model(3, 0, edited("/seed", -1), spec, model.payload), "seed: expected an integer"});
  models.push_back({raw_model(3, 0, edited("/env/name", "jaka_button"), spec, model.payload), "trained on"});
  models.push_back({raw_model(3, 0, edited("/env/name", "nope"), spec, model.payload), "unknown environment"});
  models.push_back({raw_model(3, 0, edited("/network/hidden_sizes", nlohmann::json::array({16})), spec, model.payload),
                    "shape"});
  models.push_back({raw_model(3, 0, edited("/network/hidden_sizes", nlohmann::json::array({65536, 65536})), spec, model.payload),
                    "this run would need about"});
  models.push_back({raw_model(3, 0, edited("/ppo/n_steps", 0), spec, model.payload), "ppo.n_steps"});
  models.push_back({raw_model(3, 0, edited("/algorithm", "dqn"), spec, model.payload), "algorithm"});
  models.push_back({raw_model(3, 0, cfg, "inmoov_tomato: observation float32 {6}, actions discrete 6", model.payload), "trained on"});
  // Weights: NaN, infinity, shapes and counts that differ, a damaged tensor header, trailing bytes.
  const CheckpointLayout ml = walk(ckpt.payload);  // the model payload is the checkpoint's first part
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, ml.first_weight, std::numeric_limits<float>::quiet_NaN())),
                    "not finite"});
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, ml.first_weight + 8, std::numeric_limits<float>::infinity())),
                    "not finite"});
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, 0, std::uint32_t{0x58585858})), "bad magic"});
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, 4, std::uint32_t{7})), "format version 7"});
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, 8, std::uint32_t{5})), "parameter tensors"});
  models.push_back({raw_model(3, 0, cfg, spec, with_value(model.payload, ml.tensor_rows, std::uint32_t{0x7fffffff})), "shape"});
  models.push_back({raw_model(3, 0, cfg, spec, model.payload.substr(0, model.payload.size() / 2)), "truncated"});
  models.push_back({raw_model(3, 0, cfg, spec, ""), "model.bin_"});
  models.push_back({raw_model(3, 0, cfg, spec, model.payload + "extra"), "trailing"});
  int k = 0;
  for (const auto& [bytes, expected] : models) {
    const std::string file = dir / ("model.bin_" + std::to_string(k++));
    rltest::spit(file, bytes);
    check.expect_error(file + " (" + expected + ")", {"replay", file, "-n", "1"}, {file, expected});
  }

  // --- checkpoint.bin cases: `rdsim train --resume DIR`
  const std::string& p = ckpt.payload;
  const CheckpointLayout l = walk(p);
  const std::string ccfg = ckpt.config.dump();
  const std::uint64_t huge = 1ull << 63;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<std::string, std::string>> checkpoints = {
      {raw_model(3, 0, ccfg, spec, p), "is a model, not a checkpoint"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.adam_t, huge)), "Adam state is damaged"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.adam_lr, std::numeric_limits<float>::quiet_NaN())), "Adam state is damaged"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.adam_first_moment, std::numeric_limits<float>::infinity())), "not finite"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.rng, std::uint64_t{5})), "checkpoint.bin"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.rng, std::uint64_t{1} << 60)), "does not fit"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.updates, huge)), "update count out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.progress_rows, huge)), "counters are out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.progress_rows, std::uint64_t{100000})), "rows of"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.episode_rows, std::uint64_t{1} << 55)), "counters are out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.timesteps, huge)), "counters are out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.wall, nan)), "counters are out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.wall, -5.0)), "counters are out of range"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.stateful, std::uint32_t{7})), "env-state flag"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.env_state, std::uint64_t{1} << 40)), "does not fit"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.env_state, std::uint64_t{3})), "checkpoint.bin"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.cart_x, nan)), "cartpole state is damaged"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.observation_count, std::uint64_t{3})), "observation of another shape"},
      {raw_model(3, 1, ccfg, spec, with_value(p, l.observation, std::numeric_limits<float>::infinity())), "not finite"},
      {raw_model(3, 1, ccfg, spec, p + "trailing"), "unexpected trailing data"},
      {raw_model(3, 1, ccfg, spec, p.substr(0, l.timesteps + 4)), "truncated"},
      {raw_model(3, 1, ccfg, spec, p.substr(0, l.updates)), "truncated"},
      {raw_model(3, 1, ccfg, spec, p.substr(0, 100)), "truncated"},
      {raw_model(3, 1, ccfg, "cartpole: observation float32 {5}, actions discrete 2", p), "trained on"},
  };
  {
    nlohmann::json j = ckpt.config;
    j["num_envs"] = 3;
    checkpoints.push_back({raw_model(3, 1, j.dump(), spec, p), "checkpoint.bin"});
    j = ckpt.config;
    j["network"]["hidden_sizes"] = {8, 8};
    checkpoints.push_back({raw_model(3, 1, j.dump(), spec, p), "parameter tensors"});
    j = ckpt.config;
    j["stats_window"] = 0;
    checkpoints.push_back({raw_model(3, 1, j.dump(), spec, p), "stats_window"});
  }
  const std::string ck_bytes = rltest::slurp(dir / "run/checkpoint.bin");
  checkpoints.push_back({ck_bytes.substr(0, ck_bytes.size() / 2), "truncated"});
  {
    std::string d = ck_bytes;
    d[d.size() / 2] = static_cast<char>(d[d.size() / 2] ^ 1);
    checkpoints.push_back({d, "checksum mismatch"});
  }
  k = 0;
  for (const auto& [bytes, expected] : checkpoints) {
    const std::string run = dir / ("resume" + std::to_string(k++));
    fs::create_directories(run);
    for (const char* f : {"config.json", "progress.csv", "episodes.csv", "model.bin"})
      fs::copy_file(dir / (std::string("run/") + f), run + "/" + f);
    rltest::spit(run + "/checkpoint.bin", bytes);
    check.expect_error(run + " (" + expected + ")", {"train", "--quiet", "--resume", run, "--timesteps", "512"},
                       {"checkpoint.bin", expected});
  }
  INFO(check.count << " cases, " << check.failures << " failed\n" << check.report);
  CHECK(check.failures == 0);
  CHECK(check.count >= 70);
}
