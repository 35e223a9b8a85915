#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <sys/types.h>
#include <vector>

// A real Chromium, headless, driven over the DevTools protocol through a pipe
// (--remote-debugging-pipe: JSON messages ending in a NUL byte, Chromium reads fd 3 and writes fd 4),
// so tests need neither a display, a network port nor any package beyond Debian's chromium.
namespace dashboard_test {

class HeadlessBrowser {
public:
  // Starts Chromium (RDSIM_CHROMIUM, else /usr/bin/chromium) with a fresh profile and opens a page
  // of width x height CSS pixels. Throws std::runtime_error when it cannot.
  HeadlessBrowser(int width = 1280, int height = 900);
  ~HeadlessBrowser();
  HeadlessBrowser(const HeadlessBrowser&) = delete;
  HeadlessBrowser& operator=(const HeadlessBrowser&) = delete;

  // Loads `url` and waits for its load event.
  void navigate(const std::string& url);
  // Runs a JavaScript expression in the page and returns its value (promises are awaited).
  nlohmann::json evaluate(const std::string& expression);
  // Evaluates `expression` every 50 ms until it is true or timeout_s passes; returns whether it became true.
  bool wait_until(const std::string& expression, double timeout_s);
  // A PNG of the page as it looks now.
  std::string screenshot_png();
  // Uncaught JavaScript exceptions and console errors seen so far.
  const std::vector<std::string>& page_errors() const { return errors_; }

private:
  nlohmann::json call(const std::string& method, nlohmann::json params = nlohmann::json::object(),
                      double timeout_s = 30);
  void send(const nlohmann::json& message);
  nlohmann::json receive(double timeout_s);  // the next message; throws on timeout
  void note_event(const nlohmann::json& message);

  pid_t pid_ = -1;
  int to_browser_ = -1, from_browser_ = -1;
  std::string profile_dir_, buffer_, session_;
  int next_id_ = 1;
  std::vector<nlohmann::json> events_;
  std::vector<std::string> errors_;
};

std::string base64_decode(const std::string& text);

}  // namespace dashboard_test
