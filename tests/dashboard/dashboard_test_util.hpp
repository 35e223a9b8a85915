#pragma once
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "../scratch_dir.hpp"

// Helpers shared by the dashboard tests: scratch run folders and a raw HTTP client that sends
// exactly the bytes given (httplib's client would tidy a malicious request up).
namespace dashboard_test {

namespace fs = std::filesystem;

inline fs::path scratch_dir(const std::string& name) {
  static const rdsim::test::ScratchDir root("dashboard");  // removed when the test program exits
  const fs::path dir = root.path / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline void write_file(const fs::path& file, const std::string& text, bool append = false) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, append ? std::ios::app | std::ios::binary : std::ios::trunc | std::ios::binary);
  out << text;
}

// A run folder as `rdsim train` leaves it, with a progress.csv of `rows` rows.
inline void make_run(const fs::path& dir, const std::string& algorithm, int seed, int rows) {
  write_file(dir / "config.json", "{\"algorithm\": \"" + algorithm + "\", \"env\": {\"name\": \"jaka_button\"}, \"seed\": " +
                                      std::to_string(seed) + "}\n");
  std::string csv = "timesteps,updates,episodes,mean_return,min_return,max_return,mean_length,success_rate,"
                    "policy_loss,value_loss,entropy,approx_kl,steps_per_s,wall_time\n";
  for (int i = 1; i <= rows; ++i) {
    const double p = static_cast<double>(i) / rows;
    csv += std::to_string(i * 1000) + "," + std::to_string(i) + "," + std::to_string(i * 5) + "," +
           std::to_string(-100 + 90 * p) + ",-150,0," + std::to_string(200 - 150 * p) + "," + std::to_string(p) +
           ",-0.01,0.5," + std::to_string(1.7 - p) + ",0.01,9000," + std::to_string(i * 0.1) + "\n";
  }
  write_file(dir / "progress.csv", csv);
}

// Sends `request` to 127.0.0.1:port and returns everything the server answers until it closes the
// connection or is quiet for `quiet_ms`.
// A connection to 127.0.0.1:port that is held open; -1 when it cannot connect.
inline int connect_to(int port) {
  const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(sock, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(sock);
    return -1;
  }
  return sock;
}

inline std::string raw_http(int port, const std::string& request, int quiet_ms = 2000) {
  const int sock = connect_to(port);
  if (sock < 0) return "";
  std::size_t sent = 0;
  while (sent < request.size()) {
    const ssize_t n = ::send(sock, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server hung up: it refused the request
    sent += static_cast<std::size_t>(n);
  }
  std::string answer;
  char buf[4096];
  for (;;) {
    pollfd p{sock, POLLIN, 0};
    if (::poll(&p, 1, quiet_ms) <= 0) break;
    const ssize_t n = ::recv(sock, buf, sizeof buf, 0);
    if (n <= 0) break;
    answer.append(buf, static_cast<std::size_t>(n));
  }
  ::close(sock);
  return answer;
}

inline std::string get(int port, const std::string& target, const std::string& extra_headers = "") {
  return raw_http(port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                            "\r\nConnection: close\r\n" + extra_headers + "\r\n");
}

// The status code of a raw answer ("HTTP/1.1 404 Not Found" -> 404), 0 when there is none.
inline int status_of(const std::string& answer) {
  if (answer.rfind("HTTP/1.", 0) != 0 || answer.size() < 12) return 0;
  return std::stoi(answer.substr(9, 3));
}

inline std::string body_of(const std::string& answer) {
  const auto end = answer.find("\r\n\r\n");
  return end == std::string::npos ? "" : answer.substr(end + 4);
}

}  // namespace dashboard_test
