// Key files as `rdsim keygen` writes them, and the link keys of a config's "env" object.
#include <catch2/catch.hpp>

#include <filesystem>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/remote/curve_keys.hpp"
#include "rdsim/remote/endpoint.hpp"
#include "rdsim/remote/remote_env_config.hpp"
#include "remote_test_util.hpp"

using namespace rdsim;
using namespace rdsim::remote;
using Catch::Matchers::Contains;

namespace {

unsigned mode_of(const std::string& path) {
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  return st.st_mode & 0777;
}

RemoteEnvConfig read_link(const nlohmann::json& env) {
  ConfigReader r(env, "run.json", "env");
  return read_remote_env_config(r);
}

}  // namespace

TEST_CASE("keys: keygen writes a readable public file and a 0600 secret file, and never overwrites",
          "[remote][keys]") {
  test::Scratch dir("keys");
  const CurveKeyPair keys = generate_curve_keys();
  CHECK(is_curve_key(keys.public_key));
  CHECK(is_curve_key(keys.secret_key));
  CHECK(keys.public_key != generate_curve_keys().public_key);
  const auto paths = write_key_files(dir / "k", "alice", keys);
  CHECK(paths[0] == dir / "k/alice.key");
  CHECK(paths[1] == dir / "k/alice.key_secret");
  CHECK(mode_of(paths[0]) == 0644);
  CHECK(mode_of(paths[1]) == 0600);
  CHECK(read_public_key(paths[0]) == keys.public_key);
  CHECK(read_public_key(paths[1]) == keys.public_key);
  const CurveKeyPair back = read_secret_key(paths[1]);
  CHECK(back.secret_key == keys.secret_key);
  CHECK_THROWS_WITH(write_key_files(dir / "k", "alice", generate_curve_keys()), Contains("already exists"));
  CHECK(read_secret_key(paths[1]).secret_key == keys.secret_key);  // untouched
  CHECK_THROWS_WITH(write_key_files(dir / "k", "../evil", keys), Contains("NAME must be"));
  // Others may read it: refused, as ssh does.
  ::chmod(paths[1].c_str(), 0644);
  CHECK_THROWS_WITH(read_secret_key(paths[1]), Contains("other users may read this secret key (mode 0644)"));
  // Not a key file.
  std::ofstream(dir / "junk.key") << "public not-a-key\n";
  CHECK_THROWS_WITH(read_public_key(dir / "junk.key"), Contains("junk.key: no public key in it"));
  CHECK_THROWS_WITH(read_public_key(dir / "missing.key"), Contains("missing.key"));
}

TEST_CASE("endpoints: loopback means 127/8, localhost or ::1 over tcp", "[remote][keys]") {
  CHECK(is_loopback_endpoint("tcp://127.0.0.1:7777"));
  CHECK(is_loopback_endpoint("tcp://127.1.2.3:*"));
  CHECK(is_loopback_endpoint("tcp://localhost:7777"));
  CHECK(is_loopback_endpoint("tcp://[::1]:7777"));
  CHECK_FALSE(is_loopback_endpoint("tcp://0.0.0.0:7777"));
  CHECK_FALSE(is_loopback_endpoint("tcp://*:7777"));
  CHECK_FALSE(is_loopback_endpoint("tcp://127.0.0.1.evil.example:7777"));
  CHECK_FALSE(is_loopback_endpoint("tcp://127.0.0.1000:7777"));
  CHECK_FALSE(is_loopback_endpoint("ipc:///tmp/x"));
  CHECK_THROWS_WITH(check_tcp_endpoint("tcp://host:70000", "x"), Contains("tcp://HOST:PORT"));
  CHECK_NOTHROW(check_tcp_endpoint("tcp://robot-lab.example:7777", "x"));
}

TEST_CASE("env link keys: read beside the env's own keys, checked, written back only when remote",
          "[remote][config]") {
  RemoteEnvConfig c = read_link({{"name", "jaka_button"}});
  CHECK_FALSE(c.enabled());
  nlohmann::json out = {{"name", "jaka_button"}};
  write_remote_env_config(c, out);
  CHECK(out.size() == 1);
  c = read_link({{"name", "jaka_button"}, {"remote", "tcp://lab:7777"}, {"server_key", "s.key"}, {"client_key", "c.key_secret"}});
  CHECK(c.remote == "tcp://lab:7777");
  CHECK(c.remote_timeout == 60.0);
  write_remote_env_config(c, out);
  // Recorded absolute (taken from the current folder), so the run's files find it from anywhere.
  CHECK(out["server_key"] == (std::filesystem::current_path() / "s.key").string());
  CHECK(out["client_key"] == (std::filesystem::current_path() / "c.key_secret").string());
  CHECK(out["remote_timeout"] == 60.0);
  CHECK_THROWS_WITH(read_link({{"server_key", "s.key"}}), Contains("run.json: env.server_key: only with \"remote\""));
  CHECK_THROWS_WITH(read_link({{"remote", "tcp://lab:7777"}, {"server_key", "s.key"}}),
                    Contains("env.client_key: give both server_key"));
  CHECK_THROWS_WITH(read_link({{"remote", "lab:7777"}}), Contains("run.json: env.remote: expected an address tcp://HOST:PORT"));
  CHECK_THROWS_WITH(read_link({{"remote", 7777}}), Contains("env.remote: expected a string"));
  CHECK_NOTHROW(read_link({{"remote", "tcp://127.0.0.1:7777"}}));  // plain text to loopback
}

TEST_CASE("keys: a missing key file names the keygen command that makes it", "[keys]") {
  CHECK_THROWS_WITH(read_public_key("nowhere/keys/server.key"),
                    Contains("nowhere/keys/server.key: cannot open: No such file or directory; make it with: "
                             "rdsim keygen server --dir nowhere/keys"));
  CHECK_THROWS_WITH(read_secret_key("alice.key_secret"), Contains("make it with: rdsim keygen alice --dir ."));
}

TEST_CASE("keys: key files are read only when regular, small and writable by their owner alone", "[remote][keys]") {
  rdsim::test::Scratch dir("key_files");
  const CurveKeyPair pair = generate_curve_keys();
  const std::vector<std::string> files = write_key_files(dir.path.string(), "alice", pair);
  const std::string pub = files[0], sec = files[1];
  CHECK(read_public_key(pub) == pair.public_key);
  // Before: a key file, or a key folder, any user could write was accepted without a word.
  ::chmod(pub.c_str(), 0666);
  CHECK_THROWS_WITH(read_public_key(pub), Contains(pub) && Contains("any user may write to this key file (mode 0666)") &&
                                              Contains("chmod o-w"));
  ::chmod(pub.c_str(), 0644);
  ::chmod(dir.path.c_str(), 0777);
  CHECK_THROWS_WITH(read_public_key(pub), Contains("any user may write to this key folder (mode 0777)"));
  CHECK_THROWS_WITH(read_secret_key(sec), Contains("any user may write to this key folder"));
  ::chmod(dir.path.c_str(), 0755);
  CHECK(read_secret_key(sec).secret_key == pair.secret_key);
  // Before: a 3 GiB secret key file was read whole (6 GiB of memory) and accepted.
  const std::string big = dir / "big.key_secret";
  {
    std::ofstream out(big);
    out << "public " << pair.public_key << "\nsecret " << pair.secret_key << "\n";
  }
  ::chmod(big.c_str(), 0600);
  std::filesystem::resize_file(big, 3ull << 30);  // sparse
  CHECK_THROWS_WITH(read_secret_key(big), Contains("more than the 4096 bytes"));
  // Before: a FIFO as the secret key blocked `rdsim serve` for ever.
  const std::string fifo = dir / "fifo.key_secret";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH(read_secret_key(fifo), Contains("is not a regular file (it is a FIFO)"));
}
