#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <memory>
#include <sys/stat.h>
#include <thread>
#include <vector>

#include "dashboard_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/dashboard/dashboard_server.hpp"

using namespace dashboard_test;

namespace {

rdsim::DashboardOptions options_for(const fs::path& root) {
  rdsim::DashboardOptions o;
  o.roots = {root.string()};
  o.bind.port = 0;
  return o;
}

nlohmann::json get_json(int port, const std::string& target) {
  const std::string answer = get(port, target);
  INFO(answer);
  REQUIRE(status_of(answer) == 200);
  return nlohmann::json::parse(body_of(answer));
}

}  // namespace

TEST_CASE("dashboard serves its embedded page and lists the runs", "[dashboard]") {
  const fs::path root = scratch_dir("page");
  make_run(root / "jaka_button" / "seed1", "ppo", 1, 3);
  make_run(root / "jaka_button" / "seed2", "a2c", 2, 3);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  REQUIRE(port > 0);
  CHECK(server.url() == "http://127.0.0.1:" + std::to_string(port) + "/");

  const std::string page = get(port, "/", "Accept-Encoding: gzip, deflate, br\r\n");
  CHECK(status_of(page) == 200);
  CHECK(page.find("Content-Encoding") == std::string::npos);  // never compressed (CPU, see bounded_server.cpp)
  CHECK(page.find("text/html") != std::string::npos);
  CHECK(body_of(page).find("uPlot.iife.min.js") != std::string::npos);
  CHECK(status_of(get(port, "/assets/dashboard.js")) == 200);
  CHECK(status_of(get(port, "/assets/vendor/uplot-1.6.32/uPlot.iife.min.js")) == 200);
  CHECK(body_of(get(port, "/assets/vendor/uplot-1.6.32/LICENSE")).find("MIT License") != std::string::npos);
  CHECK(status_of(get(port, "/assets/nothing.js")) == 404);

  const nlohmann::json runs = get_json(port, "/api/runs");
  REQUIRE(runs["runs"].size() == 2);
  CHECK(runs["runs"][0]["id"] == "0:jaka_button/seed1");
  CHECK(runs["runs"][0]["algorithm"] == "ppo");
  CHECK(runs["runs"][1]["seed"] == 2);
  CHECK(runs["poll_ms"] == 500);
}

TEST_CASE("dashboard answers only the rows written since the offset it gave", "[dashboard]") {
  const fs::path root = scratch_dir("incremental");
  const fs::path run = root / "run";
  make_run(run, "ppo", 1, 10);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  nlohmann::json p = get_json(port, "/api/progress?run=0:run&from=0");
  REQUIRE(p["rows"].size() == 10);
  CHECK(p["columns"][0] == "timesteps");
  CHECK(p["rows"][9][0] == 10000);
  const std::uint64_t next = p["next"];

  p = get_json(port, "/api/progress?run=0:run&from=" + std::to_string(next));
  CHECK(p["rows"].empty());
  CHECK(p["next"] == next);

  // New rows, among them malformed ones and a row the writer has not finished.
  write_file(run / "progress.csv",
             "11000,11,55,-5,-150,0,50,,-0.01,0.5,0.7,0.01,9000,1.1\n"  // empty success cell: null
             "garbage\n"
             "12000,12,60,-5,-150,0,50,0.9,-0.01,0.5,0.7,0.01,9000\n"   // a cell short
             "13000,13,65,-4,-150,0,50,0.95,-0.01,0.5,0.7,0.01,9000,1.3\n"
             "14000,14,70,-3,-1",
             true);
  p = get_json(port, "/api/progress?run=0:run&from=" + std::to_string(next));
  REQUIRE(p["rows"].size() == 2);
  CHECK(p["rows"][0][0] == 11000);
  CHECK(p["rows"][0][7].is_null());
  CHECK(p["rows"][1][0] == 13000);
  CHECK(p["skipped"] == 2);
  const std::uint64_t after = p["next"];
  write_file(run / "progress.csv", "50,0,50,0.97,-0.01,0.5,0.7,0.01,9000,1.4\n", true);
  p = get_json(port, "/api/progress?run=0:run&from=" + std::to_string(after));
  REQUIRE(p["rows"].size() == 1);
  CHECK(p["rows"][0][0] == 14000);
  CHECK(p["rows"][0][4] == -150);
}

TEST_CASE("dashboard serves a run's eval.csv with log=eval", "[dashboard]") {
  const fs::path root = scratch_dir("eval_log");
  const fs::path run = root / "run";
  make_run(run, "ppo", 1, 3);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  nlohmann::json p = get_json(port, "/api/progress?run=0:run&log=eval&from=0");
  CHECK(p["columns"].empty());  // no evaluation yet
  write_file(run / "eval.csv", "timesteps,mean_return,success_rate\n1000,-5.5,0.2\n2000,-3,0.6\n");
  p = get_json(port, "/api/progress?run=0:run&log=eval&from=0");
  REQUIRE(p["rows"].size() == 2);
  CHECK(p["columns"][1] == "mean_return");
  CHECK(p["rows"][1][2] == 0.6);
  CHECK(get_json(port, "/api/progress?run=0:run&log=progress&from=0")["rows"].size() == 3);
  CHECK(status_of(get(port, "/api/progress?run=0:run&log=episodes")) == 400);
}

TEST_CASE("dashboard never serves a file outside its run folders", "[dashboard]") {
  const fs::path base = scratch_dir("traversal");
  const fs::path root = base / "runs";
  make_run(root / "good", "ppo", 1, 2);
  const std::string secret = "SECRET-CONTENT-42";
  write_file(base / "secret" / "progress.csv", "secret\n" + secret + "\n");
  write_file(base / "secret.txt", secret);
  // A run folder whose progress.csv is a link to a file outside the root.
  fs::create_directories(root / "linked");
  fs::create_symlink(base / "secret" / "progress.csv", root / "linked" / "progress.csv");
  // A link to a folder outside the root.
  fs::create_directory_symlink(base / "secret", root / "outside");

  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  const nlohmann::json runs = get_json(port, "/api/runs");
  REQUIRE(runs["runs"].size() == 1);
  CHECK(runs["runs"][0]["id"] == "0:good");

  const std::vector<std::string> attacks = {
      "/../secret.txt",
      "/../../../../etc/passwd",
      "/assets/../../secret.txt",
      "/assets/..%2f..%2fsecret.txt",
      "/assets/%2e%2e/%2e%2e/secret.txt",
      "/assets//etc/passwd",
      "/assets/../dashboard_server.cpp",
      "/api/progress?run=0:../secret",
      "/api/progress?run=0:good/../../secret",
      "/api/progress?run=0:linked",
      "/api/progress?run=0:outside",
      "/api/progress?run=" + (base / "secret").string(),
      "/api/progress?run=0:%2e%2e%2fsecret",
      "/api/progress?run=1:.",
      "/api/progress?run=-1:.",
      "/api/progress?run=0:good%00/../../secret",
      "/api/progress?run=",
  };
  for (const auto& target : attacks) {
    INFO(target);
    const std::string answer = get(port, target);
    CHECK(status_of(answer) >= 400);
    CHECK(answer.find(secret) == std::string::npos);
    CHECK(answer.find("root:") == std::string::npos);
  }
  CHECK(status_of(get(port, "/api/progress?run=0:good")) == 200);  // the server still works
}

TEST_CASE("dashboard refuses oversized and unexpected requests and keeps serving", "[dashboard]") {
  const fs::path root = scratch_dir("oversized");
  make_run(root / "run", "ppo", 1, 2);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";

  // A request line too long.
  CHECK(status_of(get(port, "/api/runs?x=" + std::string(20000, 'a'))) == 414);
  // One header line too long.
  CHECK(status_of(raw_http(port, "GET / HTTP/1.1\r\n" + host + "X-Big: " + std::string(20000, 'b') + "\r\n\r\n")) == 400);
  // Headers without end: many short lines (2 MB); the cap of 64 KiB per request ends it.
  std::string flood = "GET / HTTP/1.1\r\n" + host;
  for (int i = 0; i < 40000; ++i) flood += "X-H" + std::to_string(i) + ": " + std::string(40, 'c') + "\r\n";
  flood += "\r\n";
  const std::string answer = raw_http(port, flood);
  CHECK(status_of(answer) == 400);
  // A body too large, and methods the dashboard does not serve.
  const int post = status_of(raw_http(port, "POST /api/runs HTTP/1.1\r\n" + host +
                                                "Content-Length: 1000000\r\n\r\n" + std::string(100000, 'd')));
  CHECK((post == 413 || post == 405));
  CHECK(status_of(raw_http(port, "DELETE /api/runs HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n")) == 405);
  // Bad parameters.
  CHECK(status_of(get(port, "/api/progress?run=0:run&from=-5")) == 400);
  CHECK(status_of(get(port, "/api/progress?run=0:run&from=99999999999999999999999")) == 400);
  CHECK(status_of(get(port, "/api/progress?run=0:nothing")) == 404);
  // A page from elsewhere reaching us by DNS rebinding names its own host.
  CHECK(status_of(raw_http(port, "GET /api/runs HTTP/1.1\r\nHost: evil.example:" + std::to_string(port) +
                                     "\r\nConnection: close\r\n\r\n")) == 403);
  // Still serving.
  CHECK(status_of(get(port, "/api/runs")) == 200);
}

TEST_CASE("dashboard reports an unreadable log as an error answer, not a crash", "[dashboard]") {
  const fs::path root = scratch_dir("unreadable");
  write_file(root / "run" / "progress.csv", "a,,b\n1,2,3\n");
  rdsim::DashboardServer server(options_for(root));
  const std::string answer = get(server.port(), "/api/progress?run=0:run");
  CHECK(status_of(answer) == 422);
  CHECK(body_of(answer).find("empty column name") != std::string::npos);
}

TEST_CASE("dashboard answers names that are not UTF-8 with U+FFFD, not an error", "[dashboard]") {
  const fs::path root = scratch_dir("not_utf8");
  make_run(root / "good", "ppo", 1, 3);
  write_file(root / "latin1_\xe9t\xe9" / "progress.csv", "timesteps,r\xe9" "compense\n1,2\n");
  rdsim::DashboardServer server(options_for(root));
  const nlohmann::json runs = get_json(server.port(), "/api/runs");
  REQUIRE(runs["runs"].size() == 2);  // the other run is still listed
  const nlohmann::json progress = get_json(server.port(), "/api/progress?run=0:good");
  CHECK(progress["rows"].size() == 3);
  // The damaged header of a run whose name is fine: served, the bad byte replaced.
  write_file(root / "good" / "progress.csv", "timesteps,r\xe9" "compense\n1,2\n");
  const nlohmann::json damaged = get_json(server.port(), "/api/progress?run=0:good");
  CHECK(damaged["columns"][1] == "r\xef\xbf\xbd" "compense");
}

TEST_CASE("dashboard bind addresses", "[dashboard]") {
  CHECK(rdsim::parse_bind_address("127.0.0.1:8097").port == 8097);
  CHECK(rdsim::parse_bind_address(":9000").host == "127.0.0.1");
  CHECK(rdsim::parse_bind_address("9000").port == 9000);
  CHECK(rdsim::parse_bind_address("[::1]:80").host == "::1");
  CHECK(rdsim::parse_bind_address("0.0.0.0:0").port == 0);
  CHECK_THROWS_WITH(rdsim::parse_bind_address("localhost:http"), Catch::Contains("expected HOST:PORT"));
  CHECK_THROWS_AS(rdsim::parse_bind_address("1.2.3.4:70000"), rdsim::Error);
  CHECK_THROWS_AS(rdsim::parse_bind_address(""), rdsim::Error);

  const fs::path root = scratch_dir("bind");
  rdsim::DashboardServer first(options_for(root));
  rdsim::DashboardOptions same = options_for(root);
  same.bind.port = first.port();
  CHECK_THROWS_WITH(rdsim::DashboardServer(same), Catch::Contains("cannot listen on 127.0.0.1:"));
  rdsim::DashboardOptions missing = options_for(root / "absent");
  CHECK_THROWS_WITH(rdsim::DashboardServer(missing), Catch::Contains("not a folder"));
}

TEST_CASE("dashboard stops while a browser keeps polling on a kept-alive connection", "[dashboard]") {
  const fs::path root = scratch_dir("stop");
  make_run(root / "run", "ppo", 1, 2);
  auto server = std::make_unique<rdsim::DashboardServer>(options_for(root));
  const int port = server->port();
  std::atomic<bool> done = false;
  std::atomic<int> answers = 0;
  std::thread browser([&] {
    const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
      const std::string request = "GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n";
      char buf[4096];
      const auto start = std::chrono::steady_clock::now();
      while (!done && std::chrono::steady_clock::now() - start < std::chrono::seconds(10) &&
             ::send(sock, request.data(), request.size(), MSG_NOSIGNAL) > 0) {
        pollfd p{sock, POLLIN, 0};
        if (::poll(&p, 1, 1000) <= 0 || ::recv(sock, buf, sizeof buf, 0) <= 0) break;
        ++answers;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
    ::close(sock);
  });
  while (answers < 3) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto start = std::chrono::steady_clock::now();
  server.reset();  // stops and joins
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  done = true;
  browser.join();
  CHECK(took < 5.0);  // a slice of the keep-alive wait, not "when the browser stops asking" (10 s here)
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Clients that each send one byte of a GET every `gap` until stopped: each would hold a worker
// that waits on its socket for as long as it keeps sending.
struct SlowClients {
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  SlowClients(int port, int count, std::chrono::milliseconds gap) {
    for (int k = 0; k < count; ++k)
      threads.emplace_back([this, port, gap] {
        const int sock = connect_to(port);
        const std::string request = "GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n";
        for (std::size_t i = 0; sock >= 0 && !stop && i < request.size(); ++i) {
          if (::send(sock, &request[i], 1, MSG_NOSIGNAL) != 1) break;
          for (auto waited = std::chrono::milliseconds(0); !stop && waited < gap; waited += std::chrono::milliseconds(10))
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (sock >= 0) ::close(sock);
      });
  }
  ~SlowClients() {
    stop = true;
    for (auto& t : threads) t.join();
  }
};

}  // namespace

TEST_CASE("dashboard: slow and idle clients cannot hold up a well-behaved one", "[dashboard][slow-clients]") {
  const fs::path root = scratch_dir("slow_clients");
  make_run(root / "run", "ppo", 1, 2);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  // Before: four sockets sending a byte a second held all four workers, and 20 idle connections
  // delayed a request by 22 s.
  SlowClients slow(port, 8, std::chrono::milliseconds(300));
  std::vector<int> idle;
  for (int k = 0; k < 200; ++k) idle.push_back(connect_to(port));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (int k = 0; k < 5; ++k) {
    const auto start = std::chrono::steady_clock::now();
    const std::string answer = raw_http(port, "GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                                  "\r\nConnection: close\r\n\r\n", 5000);
    CHECK(status_of(answer) == 200);
    CHECK(seconds_since(start) < 1.0);
  }
  CHECK(server.open_connections() <= server.max_connections());
  // Stopping does not wait for them either.
  const auto start = std::chrono::steady_clock::now();
  server.stop();
  CHECK(seconds_since(start) < 1.0);
  for (int fd : idle)
    if (fd >= 0) ::close(fd);
}

TEST_CASE("dashboard: open connections are bounded, the oldest idle one makes room", "[dashboard][slow-clients]") {
  const fs::path root = scratch_dir("bounded_connections");
  make_run(root / "run", "ppo", 1, 2);
  rdsim::DashboardOptions o = options_for(root);
  o.max_connections = 64;
  rdsim::DashboardServer server(o);
  const int port = server.port();
  const int bound = server.max_connections();
  REQUIRE(bound == 64);
  std::vector<int> idle;
  for (int k = 0; k < bound + 50; ++k) idle.push_back(connect_to(port));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK(server.open_connections() <= bound);
  CHECK(status_of(get(port, "/api/runs")) == 200);
  for (int fd : idle)
    if (fd >= 0) ::close(fd);
}

TEST_CASE("dashboard: a FIFO for a run file answers an error at once, never blocks", "[dashboard][special-files]") {
  const fs::path root = scratch_dir("fifo");
  make_run(root / "good", "ppo", 1, 2);
  write_file(root / "fifo_run" / "config.json", "{\"algorithm\": \"ppo\"}\n");
  REQUIRE(::mkfifo((root / "fifo_run" / "progress.csv").c_str(), 0600) == 0);
  fs::create_directories(root / "fifo_config");
  REQUIRE(::mkfifo((root / "fifo_config" / "config.json").c_str(), 0600) == 0);
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  // Before: the worker opening the FIFO waited for a writer, and the dashboard with it.
  const auto start = std::chrono::steady_clock::now();
  const std::string answer = get(port, "/api/progress?run=0:fifo_run");
  CHECK(status_of(answer) == 422);
  CHECK_THAT(body_of(answer), Catch::Contains("is not a regular file (it is a FIFO)"));
  CHECK(status_of(get(port, "/api/runs")) == 200);
  CHECK(status_of(get(port, "/api/progress?run=0:good")) == 200);
  CHECK(seconds_since(start) < 2.0);
}

TEST_CASE("dashboard: a progress.csv link flipped in and out of the root is never followed out", "[dashboard]") {
  const fs::path base = scratch_dir("flip");
  const fs::path root = base / "runs";
  make_run(root / "inside", "ppo", 1, 2);
  const std::string secret = "SECRET-FLIP-77";
  write_file(base / "secret" / "progress.csv", "secret\n" + secret + "\n");
  fs::create_directories(root / "flip");
  write_file(root / "flip" / "config.json", "{\"algorithm\": \"ppo\"}\n");
  fs::create_symlink("../inside/progress.csv", root / "flip" / "progress.csv");
  rdsim::DashboardServer server(options_for(root));
  const int port = server.port();
  std::atomic<bool> done{false};
  // Before: the link was checked, then opened by name: a swap in between served the outside file.
  std::thread flipper([&] {
    for (int k = 0; !done; ++k) {
      const fs::path tmp = root / "flip" / "next.lnk";
      std::error_code ec;
      fs::remove(tmp, ec);
      if (k % 2) fs::create_symlink("../inside/progress.csv", tmp, ec);
      else fs::create_symlink(base / "secret" / "progress.csv", tmp, ec);
      fs::rename(tmp, root / "flip" / "progress.csv", ec);
      // A pause between flips, longer on the inside link: on a loaded machine a flipper that never
      // stops could change the link during every request, which the server then refuses, so none
      // would ever be served.
      std::this_thread::sleep_for(std::chrono::microseconds(k % 2 ? 200 : 20));
    }
  });
  int leaks = 0, served = 0;
  const int sock = connect_to(port);
  REQUIRE(sock >= 0);
  for (int k = 0; k < 3000; ++k) {
    const std::string answer = get(port, "/api/progress?run=0:flip");
    leaks += answer.find(secret) != std::string::npos;
    served += status_of(answer) == 200;
  }
  ::close(sock);
  done = true;
  flipper.join();
  CHECK(leaks == 0);
  // The link inside the root is followed. Checked once the flipping stops: on a loaded machine the
  // flipper can change the link during every one of the requests above, which are then refused.
  INFO(served << " of 3000 requests served while the link flipped");
  const fs::path tmp = root / "flip" / "next.lnk";
  fs::remove(tmp);
  fs::create_symlink("../inside/progress.csv", tmp);
  fs::rename(tmp, root / "flip" / "progress.csv");
  // A scan made while the link pointed outside left the run out of the index; the index rescans at
  // most every 200 ms (run_index.cpp), so the run is back within a few of those.
  int status = 0;
  for (int k = 0; k < 50 && status != 200; ++k) {
    status = status_of(get(port, "/api/progress?run=0:flip"));
    if (status != 200) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  CHECK(status == 200);
}
