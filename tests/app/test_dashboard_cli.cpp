#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <cstdio>
#include <regex>
#include <sys/socket.h>
#include <unistd.h>

#include "rl_test_util.hpp"

using Catch::Matchers::Contains;

namespace {

// GET `target` from 127.0.0.1:port; the body, or "" when nothing answers.
std::string http_get(int port, const std::string& target) {
  const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (::connect(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                "\r\nConnection: close\r\n\r\n";
    if (::send(sock, request.data(), request.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(request.size())) {
      char buf[4096];
      for (ssize_t n; (n = ::recv(sock, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(n));
    }
  }
  ::close(sock);
  const auto body = answer.find("\r\n\r\n");
  return body == std::string::npos ? "" : answer.substr(body + 4);
}

int port_in(const std::string& line) {
  std::smatch m;
  const std::regex url("http://127\\.0\\.0\\.1:(\\d+)/");
  return std::regex_search(line, m, url) ? std::stoi(m[1]) : -1;
}

}  // namespace

TEST_CASE("train --dashboard serves the run being trained from the same process", "[cli][dashboard]") {
  rltest::ScratchDir dir("cli_dashboard_train");
  const std::string run = dir / "cartpole_run";
  const std::string command = std::string(RDSIM_BINARY) + " train --config configs/cartpole_ppo.json --timesteps 30000 " +
                              "--log-dir " + run + " --dashboard 127.0.0.1:0 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  REQUIRE(pipe);
  char line[4096];
  REQUIRE(std::fgets(line, sizeof line, pipe));  // the first line names the address
  const int port = port_in(line);
  INFO(line);
  REQUIRE(port > 0);
  const auto runs = nlohmann::json::parse(http_get(port, "/api/runs"));  // while it trains
  REQUIRE(runs["runs"].size() == 1);
  CHECK(runs["runs"][0]["label"] == "cartpole_run");
  CHECK(runs["runs"][0]["algorithm"] == "ppo");
  CHECK(http_get(port, "/").find("rdsim dashboard") != std::string::npos);
  std::string rest;
  while (std::fgets(line, sizeof line, pipe)) rest += line;
  CHECK(::pclose(pipe) == 0);
  CHECK_THAT(rest, Contains("30208/30208 steps (100%)"));
  CHECK(http_get(port, "/api/runs").empty());  // it stopped with the training
}

TEST_CASE("rdsim dashboard serves folders for a while, bad addresses fail clearly", "[cli][dashboard]") {
  rltest::ScratchDir dir("cli_dashboard");
  std::filesystem::create_directories(dir.path / "runs");
  const auto r = rltest::run_rdsim("dashboard " + dir / "runs" + " --bind 127.0.0.1:0 --for 0.5", dir);
  CHECK(r.exit_code == 0);
  CHECK(port_in(r.out) > 0);
  auto bad = rltest::run_rdsim("dashboard " + dir / "runs" + " --bind localhost:http --for 1", dir);
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.err, Contains("expected HOST:PORT"));
  bad = rltest::run_rdsim("dashboard " + dir / "absent" + " --bind 127.0.0.1:0 --for 1", dir);
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.err, Contains("not a folder"));
  bad = rltest::run_rdsim("train --config configs/cartpole_ppo.json --timesteps 100 --log-dir " + dir / "x" +
                              " --dashboard 192.0.2.1:8097",
                          dir);
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.err, Contains("cannot listen on 192.0.2.1:8097"));
}
