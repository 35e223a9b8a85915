// The dashboard page in a real headless Chromium: it draws a run's curves and follows its CSV
// as it grows, malformed and half-written rows included.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "dashboard_test_util.hpp"
#include "headless_browser.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/dashboard/dashboard_server.hpp"

using namespace dashboard_test;

namespace {

// How many pixels of the first chart's plotting canvas are near `hex` (#rrggbb): the line of that run.
std::string count_color_pixels_js(const std::string& column, const std::string& hex) {
  return "(() => { const c = document.querySelector('.chart[data-column=\"" + column + "\"] canvas');"
         " if (!c) return -1; const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
         " const r = parseInt('" + hex.substr(1, 2) + "', 16), g = parseInt('" + hex.substr(3, 2) + "', 16),"
         " b = parseInt('" + hex.substr(5, 2) + "', 16); let n = 0;"
         " for (let i = 0; i < d.length; i += 4) if (d[i+3] > 128 && Math.abs(d[i]-r) < 40 &&"
         " Math.abs(d[i+1]-g) < 40 && Math.abs(d[i+2]-b) < 40) ++n; return n; })()";
}

std::string row(int i) {
  const double p = i / 100.0;
  return std::to_string(i * 1000) + "," + std::to_string(i) + "," + std::to_string(i * 5) + "," +
         std::to_string(-100 + 90 * p) + ",-150,0," + std::to_string(200 - 150 * p) + "," + std::to_string(p) +
         ",-0.01,0.5," + std::to_string(1.7 - p) + ",0.01,9000," + std::to_string(i * 0.1) + "\n";
}

}  // namespace

TEST_CASE("dashboard page draws a growing run in headless Chromium and follows new rows", "[dashboard][browser]") {
  const fs::path root = scratch_dir("browser");
  const fs::path run = root / "jaka_button" / "seed1";
  make_run(run, "ppo", 1, 40);
  make_run(root / "jaka_button" / "seed2", "a2c", 2, 30);
  rdsim::DashboardOptions options;
  options.roots = {root.string()};
  options.bind.port = 0;
  options.poll_ms = 200;
  rdsim::DashboardServer server(options);

  HeadlessBrowser browser;
  browser.navigate(server.url());
  const std::string id = "0:jaka_button/seed1";
  const std::string last_x = "window.rdsimDashboard.lastX['" + id + "']";
  REQUIRE(browser.wait_until(last_x + " === 40000", 30));
  CHECK(browser.evaluate("window.rdsimDashboard.charts") == 8);  // PPO's columns: no TD loss chart
  CHECK(browser.evaluate("document.querySelectorAll('#runs input[type=checkbox]').length") == 2);
  // The first run's line (first colour) is on the success-rate canvas.
  const int drawn = browser.evaluate(count_color_pixels_js("success_rate", "#1f77b4")).get<int>();
  CHECK(drawn > 200);

  // The run's evaluations (eval.csv, a run with "eval") get charts of their own.
  write_file(run / "eval.csv",
             "timesteps,episodes,mean_return,std_return,min_return,max_return,mean_length,success_rate,new_best,seconds\n"
             "10000,10,-80,5,-90,-70,150,0.1,1,0.2\n20000,10,-40,5,-50,-30,100,0.5,1,0.2\n"
             "30000,10,-20,5,-30,-10,60,0.9,1,0.2\n");
  REQUIRE(browser.wait_until("window.rdsimDashboard.evalRows['" + id + "'] === 3", 20));
  CHECK(browser.evaluate("window.rdsimDashboard.charts") == 10);
  CHECK(browser.evaluate(count_color_pixels_js("eval:success_rate", "#1f77b4")).get<int>() > 100);

  // The run keeps training: rows arrive, one of them garbled and the last half-written.
  write_file(run / "progress.csv", row(41) + "this is not a row\n" + row(42) + "43000,43,215,-6", true);
  REQUIRE(browser.wait_until(last_x + " === 42000", 20));
  write_file(run / "progress.csv", row(43).substr(std::string("43000,43,215,-6").size()) + row(44), true);
  REQUIRE(browser.wait_until(last_x + " === 44000", 20));
  CHECK(browser.evaluate("window.rdsimDashboard.rows['" + id + "']") == 44);
  CHECK(browser.evaluate("document.getElementById('runs').textContent.includes('1 malformed skipped')") == true);

  // The controls redraw without errors.
  browser.evaluate("document.getElementById('log-scale').click(), 0");
  browser.evaluate("(() => { const s = document.getElementById('smoothing'); s.value = '0.9';"
                   " s.dispatchEvent(new Event('input')); return 0; })()");
  const int draws = browser.evaluate("window.rdsimDashboard.draws").get<int>();
  CHECK(draws >= 3);
  CHECK(browser.evaluate("window.rdsimDashboard.errors.length") == 0);
  CHECK(browser.page_errors().empty());

  const std::string png = browser.screenshot_png();
  REQUIRE(png.size() > 10000);
  CHECK(png.substr(0, 8) == "\x89PNG\r\n\x1a\n");
  const char* out = std::getenv("RDSIM_DASHBOARD_SCREENSHOT");  // where to keep it, if asked
  write_file(out && *out ? fs::path(out) : root / "dashboard.png", png);
}

// Benchmark, not run by ctest (hidden tag): a CSV growing by 1,000 rows/s, written by the trainer's
// own CsvWriter, and how long each row takes to appear on the page. A row's latency is the time
// from its write to the first draw whose data includes it.
//   RDSIM_LATENCY_S=30 build/test_dashboard "[.latency]"
TEST_CASE("dashboard latency from CSV row to plot at 1,000 rows/s", "[.latency]") {
  const char* seconds_env = std::getenv("RDSIM_LATENCY_S");
  const double seconds = seconds_env ? std::atof(seconds_env) : 30.0;
  const fs::path root = scratch_dir("latency");
  const fs::path run = root / "run";
  make_run(run, "ppo", 1, 0);
  rdsim::DashboardOptions options;
  options.roots = {root.string()};
  options.bind.port = 0;
  rdsim::DashboardServer server(options);  // the default poll interval (500 ms)
  HeadlessBrowser browser;
  browser.navigate(server.url());
  REQUIRE(browser.wait_until("window.rdsimDashboard.draws >= 0", 10));

  using Clock = std::chrono::system_clock;
  auto now_ms = [] {
    return std::chrono::duration<double, std::milli>(Clock::now().time_since_epoch()).count();
  };
  std::vector<double> written_ms;  // written_ms[i]: when the row with timesteps i+1 was written
  written_ms.reserve(static_cast<std::size_t>(seconds * 1000) + 10);
  std::atomic<bool> done = false;
  std::thread writer([&] {
    rdsim::CsvWriter csv((run / "progress.csv").string(),
                         {"timesteps", "updates", "episodes", "mean_return", "min_return", "max_return",
                          "mean_length", "success_rate", "policy_loss", "value_loss", "entropy", "approx_kl",
                          "steps_per_s", "wall_time"},
                         0);
    const auto start = std::chrono::steady_clock::now();
    for (long long i = 1; i <= static_cast<long long>(seconds * 1000); ++i) {
      // 1,000 rows/s: row i is due at i ms.
      std::this_thread::sleep_until(start + std::chrono::microseconds(i * 1000));
      const double p = static_cast<double>(i % 1000) / 1000.0;
      using rdsim::CsvWriter;
      csv.write_row({CsvWriter::cell(i), CsvWriter::cell(i), CsvWriter::cell(i / 10), CsvWriter::cell(-100 + 90 * p),
                     "-150", "0", CsvWriter::cell(200 - 150 * p), CsvWriter::cell(p), "-0.01", "0.5", "1.2", "0.01",
                     "9000", CsvWriter::cell(static_cast<double>(i) / 1000)});
      written_ms.push_back(now_ms());
    }
    done = true;
  });

  // Sample what the page last drew (its value of x and when) until the writer is done and drawn.
  std::vector<std::pair<double, double>> draws;  // (last x drawn, drawn at ms)
  const std::string probe = "[window.rdsimDashboard.lastX['0:run'] || 0, window.rdsimDashboard.drawnAt]";
  while (!done || draws.empty() || draws.back().first < seconds * 1000) {
    const nlohmann::json v = browser.evaluate(probe);
    const std::pair<double, double> d{v[0].get<double>(), v[1].get<double>()};
    if (d.first > 0 && (draws.empty() || d.second != draws.back().second)) draws.push_back(d);
    if (done && now_ms() - written_ms.back() > 10000) break;  // the page stopped following
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  writer.join();
  REQUIRE(!draws.empty());
  REQUIRE(draws.back().first == static_cast<double>(written_ms.size()));

  std::vector<double> latency;  // per draw: the oldest newly shown row's wait
  double shown = 0;
  for (const auto& [x, at] : draws) {
    if (x <= shown) continue;
    latency.push_back(at - written_ms[static_cast<std::size_t>(shown)]);  // row shown+1 is index shown
    shown = x;
  }
  std::sort(latency.begin(), latency.end());
  const double median = latency[latency.size() / 2];
  const double p95 = latency[std::min(latency.size() - 1, latency.size() * 95 / 100)];
  std::printf("dashboard latency at 1,000 rows/s for %.0f s (%zu rows, %zu draws): worst row per draw "
              "median %.0f ms, 95th percentile %.0f ms, max %.0f ms\n",
              seconds, written_ms.size(), latency.size(), median, p95, latency.back());
  CHECK(latency.back() <= 2000);
  CHECK(browser.page_errors().empty());
}

// Not run by ctest: a screenshot of the dashboard serving existing run folders, for docs/.
//   RDSIM_SCREENSHOT_RUNS=runs/a:runs/b RDSIM_DASHBOARD_SCREENSHOT=docs/dashboard.png build/test_dashboard "[.screenshot]"
TEST_CASE("dashboard screenshot of existing runs", "[.screenshot]") {
  const char* runs = std::getenv("RDSIM_SCREENSHOT_RUNS");
  const char* out = std::getenv("RDSIM_DASHBOARD_SCREENSHOT");
  REQUIRE(runs);
  REQUIRE(out);
  rdsim::DashboardOptions options;
  for (std::string rest = runs; !rest.empty();) {
    const auto colon = rest.find(':');
    options.roots.push_back(rest.substr(0, colon));
    rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
  }
  options.bind.port = 0;
  rdsim::DashboardServer server(options);
  HeadlessBrowser browser(1280, 1100);
  browser.navigate(server.url());
  REQUIRE(browser.wait_until("window.rdsimDashboard.charts > 0", 30));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // every run's rows in
  write_file(out, browser.screenshot_png());
}
