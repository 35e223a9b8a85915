// Remote envs through the real binary: training over the link gives the same logs as training in
// process; `rdsim keygen` and `rdsim serve` as a user runs them.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <regex>
#include <thread>

#include "../remote/remote_test_util.hpp"
#include "process_util.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

// configs/jaka_button.json with its env keys replaced by `env` (a JSON object's members).
std::string jaka_config(const ScratchDir& dir, const std::string& name, const std::string& env_extra,
                        long long timesteps) {
  nlohmann::json c = nlohmann::json::parse(rltest::slurp("configs/jaka_button.json"));
  const nlohmann::json extra = nlohmann::json::parse("{" + env_extra + "}");
  for (auto& [key, value] : extra.items()) c["env"][key] = value;
  c["total_timesteps"] = timesteps;
  const std::string path = dir / (name + ".json");
  rltest::spit(path, c.dump(2));
  return path;
}

nlohmann::json without_link_keys(nlohmann::json config) {
  for (const char* key : {"remote", "server_key", "client_key", "remote_timeout"}) config["env"].erase(key);
  return config;
}

std::vector<std::string> split_serve_args() { return {"serve", "--insecure", "--bind", "tcp://127.0.0.1:*"}; }

// The address `rdsim serve` prints on start ("listening on tcp://127.0.0.1:PORT"); empty if none within 30 s.
std::string wait_for_endpoint(const std::string& out_path) {
  const std::regex listening("listening on (tcp://127\\.0\\.0\\.1:[0-9]+)");
  for (int i = 0; i < 3000; ++i) {
    std::smatch m;
    const std::string out = rltest::slurp(out_path);
    if (std::regex_search(out, m, listening)) return m[1];
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return "";
}

}  // namespace

// The full-length check (300k steps, the same success as local) is tools/bench/remote.sh --learning.
TEST_CASE("train: PPO on jaka_button with a remote env (CurveZMQ) writes the same logs as with a local env",
          "[cli][remote]") {
  ScratchDir dir("cli_remote_train");
  rdsim::test::Scratch keydir("cli_remote_train_keys");
  rdsim::test::TestKeys keys(keydir);
  rdsim::test::ServerThread server(rdsim::test::curve_options(keys));
  const long long steps = 4096;  // 2 PPO updates of 8 envs x 256 steps
  const std::string local = jaka_config(dir, "local", "", steps);
  const std::string remote = jaka_config(dir, "remote",
                                         "\"remote\": \"" + server.endpoint() + "\", \"server_key\": \"" +
                                             keys.server_public + "\", \"client_key\": \"" + keys.client_secret + "\"",
                                         steps);
  auto r = run_rdsim("train --quiet --config " + local + " --log-dir " + (dir / "local"), dir);
  REQUIRE(r.exit_code == 0);
  r = run_rdsim("train --quiet --config " + remote + " --log-dir " + (dir / "remote"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(server.log(), Contains("session 8 opened: jaka_button"));  // num_envs sessions
  const std::string episodes = rltest::slurp(dir / "local/episodes.csv");
  REQUIRE(rltest::lines(episodes).size() > 10);  // episodes ended
  // All columns but wall time (the last).
  CHECK(rltest::drop_columns(rltest::slurp(dir / "remote/episodes.csv"), 1) == rltest::drop_columns(episodes, 1));
  CHECK(rltest::drop_columns(rltest::slurp(dir / "remote/progress.csv"), 2) ==
        rltest::drop_columns(rltest::slurp(dir / "local/progress.csv"), 2));
  // config.json records the env values the server used, and where the env ran.
  const auto remote_config = nlohmann::json::parse(rltest::slurp(dir / "remote/config.json"));
  const auto local_config = nlohmann::json::parse(rltest::slurp(dir / "local/config.json"));
  CHECK(remote_config["env"]["remote"] == server.endpoint());
  CHECK(without_link_keys(remote_config)["env"] == local_config["env"]);
  // The model replays through the server from its embedded config alone.
  r = run_rdsim("replay " + (dir / "remote/model.bin") + " -n 2", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("over 2 episodes"));
  // ... episode by episode as the local model does (the first line names the model file).
  const auto after_first_line = [](const std::string& out) { return out.substr(out.find('\n') + 1); };
  const std::string remote_replay = r.out;
  r = run_rdsim("replay " + (dir / "local/model.bin") + " -n 2", dir);
  CHECK(after_first_line(remote_replay) == after_first_line(r.out));
}

TEST_CASE("keygen and serve: key files, refusals and errors as a user sees them", "[cli][remote]") {
  ScratchDir dir("cli_keygen");
  auto r = run_rdsim("keygen alice --dir " + (dir / "keys"), dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("alice.key_secret (secret key, mode 0600"));
  struct stat st {};
  REQUIRE(::stat((dir / "keys/alice.key_secret").c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0600);
  r = run_rdsim("keygen alice --dir " + (dir / "keys"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("already exists"));

  r = run_rdsim("serve --insecure --bind tcp://0.0.0.0:7777", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("rdsim: error: serve: plain text (--insecure) is allowed only on a loopback address"));
  r = run_rdsim("serve --bind tcp://127.0.0.1:7777", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("give --keys DIR"));
  r = run_rdsim("keygen server --dir " + (dir / "keys"), dir);
  REQUIRE(r.exit_code == 0);
  r = run_rdsim("serve --keys " + (dir / "keys") + " --bind tcp://127.0.0.1:*", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("clients: no client public keys (*.key) in it"));
  // A config that names a server without keys for a non-loopback address never leaves the machine.
  const std::string config = dir / "remote.json";
  rltest::spit(config, R"({"env": {"name": "cartpole", "remote": "tcp://10.1.2.3:7777"}})");
  r = run_rdsim("train --config " + config, dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("env.server_key: needed for tcp://10.1.2.3:7777"));
}

// A short run of the benchmark's real path (the figures themselves are tools/bench/remote.sh's).
TEST_CASE("bench-remote: every row measured, the VecEnv rows against the same local VecEnv", "[cli][remote]") {
  ScratchDir dir("cli_bench_remote");
  const auto r = run_rdsim("bench-remote --steps 200 --runs 1 --clients 2 --envs 3 --image-size 16 --json -", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["curve"] == true);
  REQUIRE(j["rows"].size() == 5);  // GT and pixels for 1 env, 2 clients, GT and pixels for a VecEnv of 3
  for (const auto& row : j["rows"]) {
    CHECK(row["remote_steps_per_s"].get<double>() > 0.0);
    if (row["envs"] == 3) {
      CHECK(row["clients"] == 1);
      CHECK(row["in_process_steps_per_s"].get<double>() > 0.0);
      CHECK(row["p50_us"].is_null());  // one batch step is not one round trip
    } else {
      CHECK(row["p50_us"].get<double>() > 0.0);
    }
  }
  CHECK(j["rows"][4]["observation"] == "raw pixels 16x16");
}

// A model trained through `rdsim serve` replays on a local env by default: from another folder,
// with the server stopped, episode by episode as with the server (--remote).
TEST_CASE("replay: a model trained through rdsim serve replays locally from another folder with the server stopped",
          "[cli][remote]") {
  ScratchDir dir("cli_remote_replay");
  std::filesystem::create_directories(dir.path / "elsewhere");
  proctest::Child server = proctest::start(split_serve_args(), dir / "serve.out", dir / "serve.err");
  const std::string endpoint = wait_for_endpoint(dir / "serve.out");
  REQUIRE(!endpoint.empty());
  const std::string config = jaka_config(dir, "remote", "\"remote\": \"" + endpoint + "\"", 2048);
  auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string model = dir / "run/model.bin";
  // With the server: --remote.
  r = run_rdsim("replay " + model + " -n 2 --remote", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("on the server " + endpoint));
  const std::string through_server = r.out.substr(r.out.find('\n') + 1);
  ::kill(server.pid, SIGTERM);
  CHECK(proctest::wait(server, std::chrono::seconds(30)).exit_code == 0);
  // Without it, from another folder: the same episodes.
  r = rltest::run_captured("cd " + (dir / "elsewhere") + " && " + RDSIM_BINARY, "replay ../run/model.bin -n 2", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("on a local env (trained on the server " + endpoint + "; --remote replays there)"));
  CHECK(r.out.substr(r.out.find('\n') + 1) == through_server);
  // --remote with the server gone: said at once (not after remote_timeout's 60 s), naming the address.
  const auto start = std::chrono::steady_clock::now();
  r = run_rdsim("replay " + model + " -n 1 --remote", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains(endpoint + ": connection refused after 3 s: is `rdsim serve` running there?"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(30));
}

TEST_CASE("train: key file paths of a remote env are relative to the config's folder, recorded absolute, found from any folder",
          "[cli][remote]") {
  ScratchDir dir("cli_remote_keys");
  rdsim::test::Scratch keydir("cli_remote_keys_files");
  rdsim::test::TestKeys keys(keydir);
  rdsim::test::ServerThread server(rdsim::test::curve_options(keys));
  // Keys named relative to the config file's folder (dir); rdsim runs in another folder (base).
  const std::filesystem::path server_key(keys.server_public), client_key(keys.client_secret);
  const std::filesystem::path base = server_key.parent_path().parent_path();
  const std::string config = jaka_config(dir, "remote",
                                         "\"remote\": \"" + server.endpoint() + "\", \"server_key\": \"" +
                                             std::filesystem::relative(server_key, dir.path).string() + "\", \"client_key\": \"" +
                                             std::filesystem::relative(client_key, dir.path).string() + "\"",
                                         1024);
  auto r = rltest::run_captured("cd " + base.string() + " && " + RDSIM_BINARY,
                                "train --quiet --config " + config + " --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto recorded = nlohmann::json::parse(rltest::slurp(dir / "run/config.json"));
  CHECK(recorded["env"]["server_key"] == std::filesystem::absolute(server_key).lexically_normal().string());
  CHECK(recorded["env"]["client_key"] == std::filesystem::absolute(client_key).lexically_normal().string());
  // From the test's folder, through the server: the recorded paths resolve.
  r = run_rdsim("replay " + (dir / "run/model.bin") + " -n 1 --remote", dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
}
