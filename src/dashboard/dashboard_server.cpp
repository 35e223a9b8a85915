#include "rdsim/dashboard/dashboard_server.hpp"

#include <charconv>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "bounded_server.hpp"
#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/core/json_text.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/dashboard/run_index.hpp"
#include "web_assets.hpp"

namespace rdsim {
namespace {

constexpr std::size_t max_request_bytes = 64 * 1024;  // request line + headers + body
constexpr std::size_t max_body_bytes = 4 * 1024;      // GETs carry none
constexpr std::size_t max_rows_bytes = 1024 * 1024;   // of CSV per /api/progress answer

ServerLimits limits(const DashboardOptions& o) {
  ServerLimits l;
  l.max_connections = o.max_connections;
  l.max_request_bytes = max_request_bytes;
  l.max_body_bytes = max_body_bytes;
  return l;
}

bool is_loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// dump_json: bytes that are not UTF-8 (a column name in a damaged CSV, a folder name in another
// encoding) are written as U+FFFD, so one bad name cannot turn a whole answer into an error.
void send_json(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(dump_json(body), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, status, {{"error", message}});
}

// A byte offset from the query: digits only, below 2^62.
bool parse_offset(const std::string& text, std::uint64_t& out) {
  if (text.empty() || text.size() > 18) return false;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && ptr == text.data() + text.size();
}

}  // namespace

BindAddress parse_bind_address(const std::string& text) {
  BindAddress a;
  std::string port = text;
  if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    std::string host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    if (!host.empty()) a.host = host;
  }
  int value = -1;
  const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc() || ptr != port.data() + port.size() || value < 0 || value > 65535) {
    throw Error("--bind " + text + ": expected HOST:PORT with a port from 0 to 65535, e.g. 127.0.0.1:8097");
  }
  a.port = value;
  return a;
}

struct DashboardServer::Impl {
  DashboardOptions options;
  RunIndex index;
  BoundedServer server{limits(options)};
  std::set<std::string> allowed_hosts;  // Host header values accepted when bound to loopback
  int port = 0;

  explicit Impl(DashboardOptions o) : options(std::move(o)), index(options.roots) {}

  void routes();
  void runs(httplib::Response& res);
  void progress(const httplib::Request& req, httplib::Response& res);
};

void DashboardServer::Impl::routes() {
  // Connections, deadlines and threads are BoundedServer's (bounded_server.hpp); httplib parses
  // and routes each complete request.
  server.set_payload_max_length(max_body_bytes);
  server.set_keep_alive_max_count(1000);
  server.set_keep_alive_timeout(5);
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"Content-Security-Policy",
                               "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:"}});

  server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (req.method != "GET") {
      send_error(res, 405, "only GET is served");
      return httplib::Server::HandlerResponse::Handled;
    }
    // A page from another site reaching us through DNS rebinding names its own host.
    if (is_loopback(options.bind.host) && req.has_header("Host") &&
        !allowed_hosts.count(req.get_header_value("Host"))) {
      send_error(res, 403, "unexpected Host header");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  auto asset = [](const std::string& path, httplib::Response& res) {
    const web::Asset* a = web::find_asset(path);
    if (!a) return send_error(res, 404, "no such file");
    res.set_header("Cache-Control", "no-cache");
    res.set_content(reinterpret_cast<const char*>(a->bytes), a->size, web::content_type(path));
  };
  server.Get("/", [asset](const httplib::Request&, httplib::Response& res) { asset("index.html", res); });
  server.Get(R"(/assets/(.+))", [asset](const httplib::Request& req, httplib::Response& res) {
    asset(req.matches[1].str(), res);  // looked up in the embedded table, never on disk
  });
  server.Get("/api/runs", [this](const httplib::Request&, httplib::Response& res) { runs(res); });
  server.Get("/api/progress", [this](const httplib::Request& req, httplib::Response& res) { progress(req, res); });
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) {
      res.set_content(nlohmann::json{{"error", "HTTP " + std::to_string(res.status)}}.dump(), "application/json");
    }
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    send_error(res, 500, "internal error");
  });
}

void DashboardServer::Impl::runs(httplib::Response& res) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& run : index.runs()) {
    list.push_back({{"id", run.id},
                    {"label", run.label},
                    {"env", run.info.env},
                    {"algorithm", run.info.algorithm},
                    {"seed", run.info.seed ? nlohmann::json(*run.info.seed) : nlohmann::json()}});
  }
  send_json(res, 200, {{"poll_ms", options.poll_ms}, {"runs", list}});
}

void DashboardServer::Impl::progress(const httplib::Request& req, httplib::Response& res) {
  std::uint64_t from = 0;
  if (req.has_param("from") && !parse_offset(req.get_param_value("from"), from)) {
    return send_error(res, 400, "from: expected a byte offset");
  }
  // progress.csv, or with log=eval the run's evaluations (eval.csv)
  const char* name = progress_csv_name;
  if (req.has_param("log")) {
    const std::string log = req.get_param_value("log");
    if (log == "eval")
      name = eval_csv_name;
    else if (log != "progress")
      return send_error(res, 400, "log: expected progress or eval");
  }
  const auto run = index.find(req.get_param_value("run"));
  if (!run) return send_error(res, 404, "no such run");
  CsvRows rows;  // stays empty while the run has not written the log yet
  try {
    // Opened below its root in one step: a link that leads out of the root, wherever it is on
    // the way, is refused by the open itself (input_file.hpp), and a FIFO never blocks it.
    std::optional<InputFile> log = index.open_log(*run, name);
    if (log) rows = read_csv_rows(std::move(*log), from, max_rows_bytes);
  } catch (const RunOutsideRoot&) {
    return send_error(res, 404, "no such run");
  } catch (const Error& e) {
    return send_error(res, 422, e.what());
  }
  nlohmann::json body = {{"columns", rows.columns},
                         {"rows", rows.rows},  // NaN (an empty cell) is written as null
                         {"next", rows.next},
                         {"skipped", rows.skipped},
                         {"restarted", rows.restarted},
                         {"more", rows.more}};
  send_json(res, 200, body);
}

DashboardServer::DashboardServer(DashboardOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  Impl& m = *impl_;
  m.routes();
  const std::string& host = m.options.bind.host;
  m.port = m.server.bind_and_listen(host, m.options.bind.port);
  if (m.port <= 0) {
    throw Error("dashboard: cannot listen on " + host + ":" + std::to_string(m.options.bind.port) +
                " (is the port in use, or the address not one of this machine's?)");
  }
  for (std::string name : {host, std::string("localhost"), std::string("127.0.0.1"), std::string("[::1]")}) {
    m.allowed_hosts.insert(name.append(":").append(std::to_string(m.port)));
  }
  m.server.start();
}

DashboardServer::~DashboardServer() { stop(); }

void DashboardServer::stop() {
  if (impl_) impl_->server.stop();  // within a fraction of a second, whatever the clients do
}

int DashboardServer::open_connections() const { return impl_->server.open_connections(); }
int DashboardServer::max_connections() const { return impl_->server.max_connections(); }

int DashboardServer::port() const { return impl_->port; }

std::string DashboardServer::url() const {
  const std::string& host = impl_->options.bind.host;
  const bool v6 = host.find(':') != std::string::npos;
  const std::string shown = host == "0.0.0.0" ? "127.0.0.1" : (v6 ? "[" + host + "]" : host);
  return "http://" + shown + ":" + std::to_string(impl_->port) + "/";
}

}  // namespace rdsim
