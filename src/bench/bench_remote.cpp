// `rdsim bench-remote`: remote env steps/s and latency next to in-process steps/s, one run.
#include "rdsim/bench/bench_remote.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <latch>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <thread>

#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/bench/bench_run.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/curve_keys.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "rdsim/remote/server.hpp"

namespace rdsim {
namespace {

using Clock = std::chrono::steady_clock;

// CPU seconds this process has used so far, all threads (user + system). Per-step CPU time is far
// less sensitive than steps/s to other programs sharing the cores: those delay our threads but do
// not bill their time to us.
double process_cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

// A temporary folder with the bench's client key files, removed at the end.
struct KeyFolder {
  std::filesystem::path path;
  KeyFolder() {
    std::string templ = (std::filesystem::temp_directory_path() / "rdsim_bench_remote_XXXXXX").string();
    if (!::mkdtemp(templ.data())) throw Error("bench-remote: cannot make a temporary folder");
    path = templ;
  }
  ~KeyFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// The serve engine on its own thread for the bench's lifetime.
struct LocalServer {
  remote::Server server;
  std::thread thread;
  explicit LocalServer(remote::ServerOptions o) : server(std::move(o)), thread([this] { server.run(); }) {}
  ~LocalServer() {
    server.stop();
    thread.join();
  }
};

struct Row {
  std::string what;
  int clients = 1;
  int envs = 1;           // envs per client (> 1: one VecEnv on one thread)
  double in_process = 0;  // steps/s, median; 0 when not measured
  double remote = 0;      // steps/s, median (all clients together)
  double p50_us = 0, p99_us = 0;
  // CPU time per step, µs, over all timed runs: in process (the env alone), and remote (client,
  // server, ZeroMQ I/O threads and the kernel's socket work for that step, all together).
  double in_cpu_us = 0, remote_cpu_us = 0;
};

double in_process_rate(const EnvConfig& config, const BenchRemoteOptions& o, double& cpu_us) {
  const auto env = make_env(config);
  long long episodes = 0;
  env_run(*env, std::max<long long>(o.steps / 10, 100), 12345, episodes);  // warm-up
  std::vector<double> runs;
  const double cpu0 = process_cpu_seconds();
  for (int r = 0; r < o.runs; ++r) runs.push_back(env_run(*env, o.steps, static_cast<std::uint64_t>(r), episodes));
  cpu_us = 1e6 * (process_cpu_seconds() - cpu0) / static_cast<double>(o.steps * o.runs);
  return median(runs);
}

// `clients` remote envs stepping at once; returns total steps/s per run and fills step latencies.
double remote_rate(const EnvConfig& config, const RemoteEnvConfig& link, int clients, const BenchRemoteOptions& o,
                   std::vector<double>& latencies, double& cpu_us) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int c = 0; c < clients; ++c) envs.push_back(connect_remote_env(link, config));
  long long warmup = 0;
  for (auto& env : envs) env_run(*env, std::max<long long>(o.steps / 10, 100), 12345, warmup);
  std::vector<double> runs;
  const double cpu0 = process_cpu_seconds();
  for (int r = 0; r < o.runs; ++r) {
    std::vector<std::vector<double>> seconds(static_cast<std::size_t>(clients));
    std::latch start(clients + 1);
    std::vector<std::thread> threads;
    for (int c = 0; c < clients; ++c) {
      threads.emplace_back([&, c] {
        long long episodes = 0;
        start.arrive_and_wait();
        env_run(*envs[static_cast<std::size_t>(c)], o.steps, static_cast<std::uint64_t>(r * 100 + c), episodes,
                &seconds[static_cast<std::size_t>(c)]);
      });
    }
    start.arrive_and_wait();
    const auto t0 = Clock::now();
    for (auto& t : threads) t.join();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    runs.push_back(static_cast<double>(o.steps) * clients / wall);
    for (const auto& s : seconds) latencies.insert(latencies.end(), s.begin(), s.end());
  }
  cpu_us = 1e6 * (process_cpu_seconds() - cpu0) / static_cast<double>(o.steps * o.runs * clients);
  return median(runs);
}

// One VecEnv of `envs` made by `make` stepped by this thread with random actions (drawn before
// the clock starts), resets included; returns env steps/s per run. Local envs step one after
// another; remote ones have all their requests in flight at once (Env::begin_step).
std::vector<double> vec_env_rates(const std::function<std::unique_ptr<Env>()>& make, int envs,
                                  const BenchRemoteOptions& o, double& cpu_us) {
  std::vector<std::unique_ptr<Env>> list;
  for (int e = 0; e < envs; ++e) list.push_back(make());
  VecEnv vec(std::move(list), 12345);
  Rng rng = Rng::derive(12345, 1);
  std::vector<std::vector<Action>> actions(512);
  for (auto& a : actions)
    for (int e = 0; e < envs; ++e) a.push_back(random_action(vec.spec().action, rng));
  const long long batches = std::max<long long>(o.steps / envs, 1);
  for (long long b = 0; b < std::max<long long>(batches / 10, 10); ++b) vec.step(actions[static_cast<std::size_t>(b) % 512]);
  std::vector<double> runs;
  const double cpu0 = process_cpu_seconds();
  for (int r = 0; r < o.runs; ++r) {
    const auto t0 = Clock::now();
    for (long long b = 0; b < batches; ++b) vec.step(actions[static_cast<std::size_t>(b) % 512]);
    runs.push_back(static_cast<double>(batches * envs) / std::chrono::duration<double>(Clock::now() - t0).count());
  }
  cpu_us = 1e6 * (process_cpu_seconds() - cpu0) / static_cast<double>(batches * envs * o.runs);
  return runs;
}

// One client with `envs` remote envs in one VecEnv against the same VecEnv of local envs.
Row measure_vec_env(const std::string& what, const EnvConfig& config, const RemoteEnvConfig& link, int envs,
                    const BenchRemoteOptions& o) {
  std::fprintf(stderr, "bench-remote: %s, 1 client with %d envs ...\n", what.c_str(), envs);
  Row row{what, 1, envs};
  row.in_process = median(vec_env_rates([&] { return make_env(config); }, envs, o, row.in_cpu_us));
  row.remote = median(vec_env_rates([&] { return std::unique_ptr<Env>(connect_remote_env(link, config)); }, envs, o,
                                    row.remote_cpu_us));
  return row;
}

Row measure(const std::string& what, const EnvConfig& config, const RemoteEnvConfig& link, int clients,
            const BenchRemoteOptions& o, bool with_in_process) {
  std::fprintf(stderr, "bench-remote: %s, %d client%s ...\n", what.c_str(), clients, clients == 1 ? "" : "s");
  Row row{what, clients};
  if (with_in_process) row.in_process = in_process_rate(config, o, row.in_cpu_us);
  std::vector<double> latencies;
  row.remote = remote_rate(config, link, clients, o, latencies, row.remote_cpu_us);
  row.p50_us = 1e6 * quantile(latencies, 0.50);
  row.p99_us = 1e6 * quantile(latencies, 0.99);
  return row;
}

void print_table(std::FILE* out, const std::vector<Row>& rows, const BenchRemoteOptions& o) {
  std::fprintf(out, "\nrdsim bench-remote: %s over loopback TCP, %s; random actions, resets included;\n",
               o.env.c_str(), o.insecure ? "plain text" : "CurveZMQ (encrypted, authenticated)");
  std::fprintf(out, "median of %d runs x %lld steps per client; latency = one step's request and reply\n\n", o.runs, o.steps);
  std::fprintf(out, "%-24s %8s %5s %14s %14s %10s %10s %10s %12s %12s\n", "observation", "clients", "envs",
               "in-process/s", "remote/s", "remote/in", "p50 us", "p99 us", "cpu us in", "cpu us rem");
  for (const Row& r : rows) {
    char in[32] = "-", ratio[32] = "-", in_cpu[32] = "-", p50[32] = "-", p99[32] = "-";
    if (r.in_process > 0) {
      std::snprintf(in, sizeof in, "%.0f", r.in_process);
      std::snprintf(ratio, sizeof ratio, "%.2f", r.remote / r.in_process);
      std::snprintf(in_cpu, sizeof in_cpu, "%.1f", r.in_cpu_us);
    }
    if (r.envs == 1) {
      std::snprintf(p50, sizeof p50, "%.1f", r.p50_us);
      std::snprintf(p99, sizeof p99, "%.1f", r.p99_us);
    }
    std::fprintf(out, "%-24s %8d %5d %14s %14.0f %10s %10s %10s %12s %12.1f\n", r.what.c_str(), r.clients, r.envs, in,
                 r.remote, ratio, p50, p99, in_cpu, r.remote_cpu_us);
  }
  std::fprintf(out, "\ncpu us = CPU time of the whole process per step (all threads: for remote, the client, the\n"
                    "server, ZeroMQ's I/O threads and the kernel's socket work); unlike steps/s it hardly depends\n"
                    "on other programs sharing the cores\n");
  std::fprintf(out, "envs > 1: one client stepping a VecEnv of that many envs on one thread, as `rdsim train` does\n"
                    "(remote: every env's request in flight at once), against the same VecEnv of local envs\n");
  for (const Row& r : rows)
    if (r.clients > 1 && rows[0].clients == 1)
      std::fprintf(out, "\n%d clients at once: %.2fx the steps/s of one client\n", r.clients, r.remote / rows[0].remote);
}

nlohmann::json to_json(const std::vector<Row>& rows, const BenchRemoteOptions& o) {
  nlohmann::json j = {{"env", o.env}, {"runs", o.runs}, {"steps_per_client", o.steps},
                      {"curve", !o.insecure}, {"cores", std::thread::hardware_concurrency()},
                      {"rows", nlohmann::json::array()}};
  for (const Row& r : rows)
    j["rows"].push_back({{"observation", r.what}, {"clients", r.clients}, {"envs", r.envs},
                         {"in_process_steps_per_s", r.in_process > 0 ? nlohmann::json(r.in_process) : nlohmann::json(nullptr)},
                         {"remote_steps_per_s", r.remote},
                         {"p50_us", r.envs == 1 ? nlohmann::json(r.p50_us) : nlohmann::json(nullptr)},
                         {"p99_us", r.envs == 1 ? nlohmann::json(r.p99_us) : nlohmann::json(nullptr)},
                         {"in_process_cpu_us_per_step", r.in_process > 0 ? nlohmann::json(r.in_cpu_us) : nlohmann::json(nullptr)},
                         {"remote_cpu_us_per_step", r.remote_cpu_us}});
  return j;
}

}  // namespace

int bench_remote_command(const BenchRemoteOptions& o) {
  EnvConfig ground = default_env_config(o.env);
  EnvConfig pixels = ground;
  pixels.observation = ObservationMode::RawPixels;
  pixels.image_width = pixels.image_height = o.image_size;
  const bool has_pixels = env_entry(o.env).supports_pixels;
  const std::string pixels_name = "raw pixels " + std::to_string(o.image_size) + "x" + std::to_string(o.image_size);

  KeyFolder keys;
  remote::ServerOptions server;
  server.bind = "tcp://127.0.0.1:*";
  server.insecure = o.insecure;
  server.max_sessions = std::max(o.clients, o.envs) + 4;
  server.log = [](const std::string&) {};  // no session lines in the bench's output
  RemoteEnvConfig link;
  if (!o.insecure) {
    server.keys = remote::generate_curve_keys();
    const auto server_files = remote::write_key_files(keys.path.string(), "server", *server.keys);
    const remote::CurveKeyPair client = remote::generate_curve_keys();
    const auto client_files = remote::write_key_files(keys.path.string(), "client", client);
    server.authorised = {client.public_key};
    link.server_key = server_files[0];
    link.client_key = client_files[1];
  }
  LocalServer local(std::move(server));
  link.remote = local.server.endpoint();

  std::vector<Row> rows;
  rows.push_back(measure("ground truth", ground, link, 1, o, true));
  if (has_pixels)
    rows.push_back(measure(pixels_name, pixels, link, 1, o, true));
  if (o.clients > 1) rows.push_back(measure("ground truth", ground, link, o.clients, o, false));
  if (o.envs > 1) {
    rows.push_back(measure_vec_env("ground truth", ground, link, o.envs, o));
    if (has_pixels)
      rows.push_back(measure_vec_env(pixels_name, pixels, link, o.envs, o));
  }

  print_table(table_stream(o.json_path), rows, o);
  write_bench_json(o.json_path, to_json(rows, o));
  return 0;
}

}  // namespace rdsim
