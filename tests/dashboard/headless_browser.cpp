#include "headless_browser.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <thread>

namespace dashboard_test {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

std::string base64_decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  int bits = 0, acc = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;  // padding, line breaks
    acc = (acc << 6) | v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xff));
    }
  }
  return out;
}

HeadlessBrowser::HeadlessBrowser(int width, int height) {
  const char* env = std::getenv("RDSIM_CHROMIUM");
  const std::string binary = env && *env ? env : "/usr/bin/chromium";
  if (::access(binary.c_str(), X_OK) != 0) throw std::runtime_error(binary + ": not found (Debian package chromium)");
  char profile[] = "/tmp/rdsim_chromium_XXXXXX";
  if (!::mkdtemp(profile)) throw std::runtime_error("cannot make a profile folder");
  profile_dir_ = profile;

  int in[2], out[2];  // in: we write, Chromium reads (fd 3); out: Chromium writes (fd 4), we read
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  const std::string size = "--window-size=" + std::to_string(width) + "," + std::to_string(height);
  const std::string user_data = "--user-data-dir=" + profile_dir_;
  std::vector<std::string> args = {binary, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                                   "--no-first-run", "--disable-background-networking",
                                   "--disable-component-update", "--disable-sync", "--disable-extensions",
                                   "--mute-audio", "--hide-scrollbars", "--disable-dev-shm-usage", "--remote-debugging-pipe", size,
                                   user_data, "about:blank"};
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    // dup2 clears close-on-exec on the new descriptors.
    if (::dup2(in[0], 3) < 0 || ::dup2(out[1], 4) < 0) ::_exit(127);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);  // Chromium's own chatter (D-Bus, GPU) is not the test's
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(in[0]);
  ::close(out[1]);
  to_browser_ = in[1];
  from_browser_ = out[0];

  // Attach to the page Chromium opened.
  const nlohmann::json targets = call("Target.getTargets");
  std::string target;
  for (const auto& t : targets["targetInfos"]) {
    if (t["type"] == "page") target = t["targetId"];
  }
  if (target.empty()) target = call("Target.createTarget", {{"url", "about:blank"}})["targetId"];
  session_ = call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}})["sessionId"];
  call("Page.enable");
  call("Runtime.enable");
  call("Emulation.setDeviceMetricsOverride",
       {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}});
}

HeadlessBrowser::~HeadlessBrowser() {
  if (pid_ > 0) {
    try {
      session_.clear();
      send({{"id", next_id_++}, {"method", "Browser.close"}});
    } catch (...) {
    }
    const auto start = Clock::now();
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (seconds_since(start) > 5) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  if (to_browser_ >= 0) ::close(to_browser_);
  if (from_browser_ >= 0) ::close(from_browser_);
  std::error_code ec;
  if (!profile_dir_.empty()) std::filesystem::remove_all(profile_dir_, ec);
}

void HeadlessBrowser::send(const nlohmann::json& message) {
  const std::string text = message.dump() + std::string(1, '\0');
  std::size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = ::write(to_browser_, text.data() + sent, text.size() - sent);
    if (n <= 0) throw std::runtime_error("chromium: the pipe closed");
    sent += static_cast<std::size_t>(n);
  }
}

nlohmann::json HeadlessBrowser::receive(double timeout_s) {
  const auto start = Clock::now();
  for (;;) {
    const auto end = buffer_.find('\0');
    if (end != std::string::npos) {
      nlohmann::json message = nlohmann::json::parse(buffer_.substr(0, end));
      buffer_.erase(0, end + 1);
      return message;
    }
    const int left_ms = static_cast<int>((timeout_s - seconds_since(start)) * 1000);
    if (left_ms <= 0) throw std::runtime_error("chromium: no answer in time");
    pollfd p{from_browser_, POLLIN, 0};
    if (::poll(&p, 1, left_ms) <= 0) continue;
    char chunk[65536];
    const ssize_t n = ::read(from_browser_, chunk, sizeof chunk);
    if (n <= 0) throw std::runtime_error("chromium: the pipe closed (did it crash?)");
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

void HeadlessBrowser::note_event(const nlohmann::json& message) {
  const std::string method = message.value("method", "");
  if (method == "Runtime.exceptionThrown") {
    errors_.push_back(message["params"]["exceptionDetails"].dump());
  } else if (method == "Runtime.consoleAPICalled" && message["params"].value("type", "") == "error") {
    errors_.push_back(message["params"]["args"].dump());
  }
  events_.push_back(message);
}

nlohmann::json HeadlessBrowser::call(const std::string& method, nlohmann::json params, double timeout_s) {
  const int id = next_id_++;
  nlohmann::json message = {{"id", id}, {"method", method}, {"params", std::move(params)}};
  if (!session_.empty()) message["sessionId"] = session_;
  send(message);
  const auto start = Clock::now();
  for (;;) {
    nlohmann::json m = receive(timeout_s - seconds_since(start));
    if (m.contains("id") && m["id"] == id) {
      if (m.contains("error")) throw std::runtime_error("chromium: " + method + ": " + m["error"].dump());
      return m["result"];
    }
    note_event(m);
  }
}

void HeadlessBrowser::navigate(const std::string& url) {
  events_.clear();
  call("Page.navigate", {{"url", url}});
  const auto start = Clock::now();
  for (;;) {
    for (const auto& e : events_) {
      if (e.value("method", "") == "Page.loadEventFired") return;
    }
    events_.clear();
    note_event(receive(30 - seconds_since(start)));
  }
}

nlohmann::json HeadlessBrowser::evaluate(const std::string& expression) {
  const nlohmann::json r =
      call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}, {"awaitPromise", true}});
  if (r.contains("exceptionDetails")) throw std::runtime_error("page: " + r["exceptionDetails"].dump());
  return r["result"].value("value", nlohmann::json());
}

bool HeadlessBrowser::wait_until(const std::string& expression, double timeout_s) {
  const auto start = Clock::now();
  while (seconds_since(start) < timeout_s) {
    if (evaluate("!!(" + expression + ")") == true) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

std::string HeadlessBrowser::screenshot_png() {
  return base64_decode(call("Page.captureScreenshot", {{"format", "png"}})["data"].get<std::string>());
}

}  // namespace dashboard_test
