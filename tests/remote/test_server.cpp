// The server over real loopback TCP: CurveZMQ authentication, plain text only on loopback, session
// lifetimes (close, disconnect, idle timeout, cap), hostile frames, and RemoteEnv/RemoteRobotEnv
// giving what the local env gives.
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zmq.hpp>

#include <atomic>
#include <functional>
#include <limits>

#include <fstream>
#include <nlohmann/json.hpp>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/randomization.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/protocol.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "remote_test_util.hpp"

using namespace rdsim;
using namespace rdsim::test;
using Catch::Matchers::Contains;

namespace {

// A bare ZeroMQ client (plain text) that sends raw frames, as an attacker or a foreign client would.
struct RawClient {
  zmq::context_t context{1};
  zmq::socket_t socket;
  explicit RawClient(const std::string& endpoint, zmq::socket_type type = zmq::socket_type::dealer,
                     const std::function<void(zmq::socket_t&)>& setup = {})
      : socket(context, type) {
    socket.set(zmq::sockopt::linger, 0);
    if (setup) setup(socket);
    socket.connect(endpoint);
  }
  void send(const std::vector<std::string>& frames) {
    for (std::size_t i = 0; i < frames.size(); ++i)
      socket.send(zmq::buffer(frames[i]), i + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
  }
  // The reply's header, or null after `ms` without one.
  nlohmann::json receive(int ms = 5000) {
    std::vector<zmq::pollitem_t> items = {{socket.handle(), 0, ZMQ_POLLIN, 0}};
    zmq::poll(items, std::chrono::milliseconds(ms));
    if (!(items[0].revents & ZMQ_POLLIN)) return nullptr;
    std::vector<zmq::message_t> parts;
    do {
      zmq::message_t m;
      (void)socket.recv(m);
      parts.push_back(std::move(m));
    } while (parts.back().more());
    return nlohmann::json::parse(parts[0].to_string());
  }
  nlohmann::json call(const std::string& header) {
    send({header});
    return receive();
  }
};

// A TCP relay between a client and the server that records every byte the client sends: what an
// eavesdropper on the network sees.
class RecordingRelay {
public:
  explicit RecordingRelay(int server_port) : server_port_(server_port) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    REQUIRE(::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    REQUIRE(::listen(listener_, 1) == 0);
    REQUIRE(::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &len) == 0);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { relay(); });
  }
  ~RecordingRelay() {
    stop_ = true;
    thread_.join();
    ::close(listener_);
  }
  std::string endpoint() const { return "tcp://127.0.0.1:" + std::to_string(port_); }
  std::string captured() {
    std::lock_guard<std::mutex> lock(mutex_);
    return captured_;
  }

private:
  void relay() {
    pollfd l{listener_, POLLIN, 0};
    while (!stop_ && ::poll(&l, 1, 50) <= 0) {}
    if (stop_) return;
    const int client = ::accept(listener_, nullptr, nullptr);
    const int server = connect_to_server();
    pollfd fds[2] = {{client, POLLIN, 0}, {server, POLLIN, 0}};
    char buf[65536];
    while (!stop_) {
      if (::poll(fds, 2, 50) <= 0) continue;
      for (int i = 0; i < 2; ++i) {
        if (!(fds[i].revents & (POLLIN | POLLHUP))) continue;
        const ssize_t n = ::recv(fds[i].fd, buf, sizeof buf, 0);
        if (n <= 0) {
          stop_ = true;
          break;
        }
        if (i == 0) {
          std::lock_guard<std::mutex> lock(mutex_);
          captured_.append(buf, static_cast<std::size_t>(n));
        }
        (void)::send(fds[1 - i].fd, buf, static_cast<std::size_t>(n), MSG_NOSIGNAL);
      }
    }
    ::close(client);
    ::close(server);
  }
  int connect_to_server() const {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(server_port_));
    (void)::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
    return s;
  }

  int server_port_, port_ = 0, listener_ = -1;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::string captured_;
  std::thread thread_;
};

int port_of(const std::string& endpoint) { return std::stoi(endpoint.substr(endpoint.rfind(':') + 1)); }

const std::string hello_jaka = R"({"id": 1, "request": "hello", "protocol": 1, "env": {"name": "jaka_button"}})";

}  // namespace

TEST_CASE("server: an authorised CurveZMQ client gets the local env's results bit for bit", "[remote][server]") {
  Scratch dir("curve_ok");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  EnvConfig config = default_env_config("jaka_button");
  config.get<ReachOptions>().random_target = true;
  config.max_steps = 40;
  const auto remote = connect_remote_env(keys.link(server.endpoint()), config);
  const auto local = make_env(config);
  CHECK(remote->resolved_config().max_steps == 40);
  CHECK(remote->spec().observation.high == local->spec().observation.high);
  CHECK(remote->reset(9).values == local->reset(9).values);
  for (int t = 0; t < 150; ++t) {
    const Action a = Action::discrete(t % 6);
    const StepResult r = remote->step(a), l = local->step(a);
    REQUIRE(r.observation.values == l.observation.values);
    REQUIRE(r.reward == l.reward);
    REQUIRE(r.terminated == l.terminated);
    REQUIRE(r.truncated == l.truncated);
    if (l.terminated || l.truncated) REQUIRE(remote->reset().values == local->reset().values);
  }
  // Robot control over the link, against the local env's.
  auto* rc = dynamic_cast<RobotControl*>(remote.get());
  auto* lc = dynamic_cast<RobotControl*>(local.get());
  REQUIRE(rc);
  remote->reset(3);
  local->reset(3);
  for (int t = 0; t < 20; ++t) {
    const Eigen::Vector3f goal(0.4f, 0.1f, 0.2f);
    REQUIRE(rc->move_effector(goal).reward == lc->move_effector(goal).reward);
  }
  const RobotSnapshot rs = rc->robot_state(), ls = lc->robot_state();
  CHECK(rs.joint_positions == ls.joint_positions);
  CHECK(rs.effector_orientation.coeffs() == ls.effector_orientation.coeffs());
  CHECK(rc->robot_info().joints.size() == 6);
  Image ri, li;
  rc->camera_image(0, 48, 32, ri);
  lc->camera_image(0, 48, 32, li);
  CHECK(ri.rgb == li.rgb);
  CHECK_THROWS_WITH(rc->camera_image(0, 2000, 10, ri), Contains("cameras: width: expected an integer in [1, 1024]"));
  // A cartpole session is a plain RemoteEnv: no robot control to find.
  EnvConfig cartpole = default_env_config("cartpole");
  const auto cart = connect_remote_env(keys.link(server.endpoint()), cartpole);
  CHECK(dynamic_cast<RobotControl*>(cart.get()) == nullptr);
  CHECK_THAT(server.log(), Contains("opened: jaka_button for client " + keys.client.public_key + " from 127.0.0.1"));
}

TEST_CASE("server: Float32 depth and segmentation images travel bit for bit", "[remote][server]") {
  Scratch dir("curve_channels");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  EnvConfig config = default_env_config("jaka_button");
  config.observation = ObservationMode::RawPixels;
  config.image_width = 24;
  config.image_height = 16;
  config.image_channels = "rgb_depth_segmentation";
  const auto remote = connect_remote_env(keys.link(server.endpoint()), config);
  const auto local = make_env(config);
  CHECK(remote->spec().observation.shape == std::vector<int>{16, 24, 5});
  CHECK(remote->spec().observation.type == ObsType::Float32);
  CHECK(remote->spec().observation.high == local->spec().observation.high);
  CHECK(remote->reset(4).values == local->reset(4).values);
  for (int t = 0; t < 5; ++t) REQUIRE(remote->step(Action::discrete(t)).observation.values == local->step(Action::discrete(t)).observation.values);
}

TEST_CASE("server: a randomized goal env (per-episode draws, latency, queued actions) matches the local one",
          "[remote][server][randomize]") {
  Scratch dir("curve_randomized");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  EnvConfig config = default_env_config("push");
  Randomization& r = config.get<RandomizeOptions>().randomize;
  r.mass_scale = {0.7, 1.3};
  r.friction_scale = {0.5, 1.5};
  r.placement_noise = 0.01;
  r.observation_noise = 0.005;
  r.action_latency = 2;
  r.observe_latency = true;
  const auto remote = connect_remote_env(keys.link(server.endpoint()), config);
  const auto local = make_env(config);
  CHECK(remote->spec().observation.high == local->spec().observation.high);
  CHECK(remote->spec().goal.observation == local->spec().goal.observation);
  CHECK(remote->reset(6).values == local->reset(6).values);
  for (int t = 0; t < 60; ++t) {
    const Action a = Action::continuous(Eigen::Vector3f(0.3f * static_cast<float>(t % 3 - 1), 0.2f, -0.1f));
    const StepResult rr = remote->step(a), l = local->step(a);
    REQUIRE(rr.observation.values == l.observation.values);
    REQUIRE(rr.reward == l.reward);
    if (l.terminated || l.truncated) REQUIRE(remote->reset().values == local->reset().values);
  }
}

TEST_CASE("server: a client whose key is not authorised gets nothing, and the refusal is logged", "[remote][server]") {
  Scratch dir("curve_refused");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  // Mallory has her own valid pair and the server's public key, but is not in the authorised list.
  const remote::CurveKeyPair mallory = remote::generate_curve_keys();
  RemoteEnvConfig link = keys.link(server.endpoint());
  link.client_key = remote::write_key_files(dir.path.string(), "mallory", mallory)[1];
  link.remote_timeout = 10;
  CHECK_THROWS_WITH(connect_remote_env(link, default_env_config("jaka_button")),
                    Contains("the server refused this client's key"));
  CHECK(eventually([&] { return server.server().stats().refused >= 1; }));
  CHECK_THAT(server.log(), Contains("refused client key " + mallory.public_key + " from 127.0.0.1"));
  CHECK(server.server().stats().sessions_opened == 0);
  CHECK(server.server().stats().requests == 0);  // not one byte of hers reached the server's sessions
  // Someone who copied Alice's PUBLIC key file (all a captured session shows) cannot use it: the
  // handshake proves possession of the secret key.
  remote::CurveKeyPair impostor = remote::generate_curve_keys();
  const std::string forged = dir / "forged.key_secret";
  {
    std::ofstream out(forged);
    out << "public " << keys.client.public_key << "\nsecret " << impostor.secret_key << "\n";
  }
  std::filesystem::permissions(forged, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  link.client_key = forged;
  CHECK_THROWS_WITH(connect_remote_env(link, default_env_config("jaka_button")), Contains("do not belong together"));
  // A plain-text client is refused by a CurveZMQ server.
  const long long refused_before = server.server().stats().refused;
  RawClient plain(server.endpoint());
  plain.send({hello_jaka});
  CHECK(plain.receive(1000).is_null());
  CHECK(server.server().stats().sessions_opened == 0);
  // ...and counted and logged as refused, as every refused attempt is (before: neither).
  CHECK(eventually([&] { return server.server().stats().refused > refused_before; }));
  CHECK_THAT(server.log(), Contains("refused a connection that failed the CurveZMQ handshake: a plain-text client"));
}

TEST_CASE("server: a captured CurveZMQ session replayed byte for byte opens nothing", "[remote][server]") {
  Scratch dir("curve_replay");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  std::string captured;
  {
    RecordingRelay relay(port_of(server.endpoint()));
    const auto env = connect_remote_env(keys.link(relay.endpoint()), default_env_config("jaka_button"));
    env->reset(1);
    for (int t = 0; t < 10; ++t) env->step(Action::discrete(t % 6));
    captured = relay.captured();
  }
  CHECK(eventually([&] { return server.server().stats().sessions == 0; }));
  const remote::ServerStats before = server.server().stats();
  CHECK(before.sessions_opened == 1);
  REQUIRE(captured.size() > 500);
  // What the eavesdropper saw holds none of the plain text.
  CHECK(captured.find("jaka_button") == std::string::npos);
  CHECK(captured.find("\"request\"") == std::string::npos);
  // Replaying it on a new connection: the server's handshake has fresh ephemeral keys and a fresh
  // cookie, so the recorded handshake and messages do not verify and nothing reaches a session.
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port_of(server.endpoint())));
  REQUIRE(::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  (void)::send(s, captured.data(), captured.size(), MSG_NOSIGNAL);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::close(s);
  const remote::ServerStats after = server.server().stats();
  CHECK(after.sessions_opened == before.sessions_opened);
  CHECK(after.requests == before.requests);
  // Nor does presenting Alice's public key without her secret key get in.
  const remote::CurveKeyPair own = remote::generate_curve_keys();
  RawClient impostor(server.endpoint(), zmq::socket_type::dealer, [&](zmq::socket_t& socket) {
    socket.set(zmq::sockopt::curve_serverkey, keys.server.public_key);
    socket.set(zmq::sockopt::curve_publickey, keys.client.public_key);
    socket.set(zmq::sockopt::curve_secretkey, own.secret_key);
  });
  impostor.send({hello_jaka});
  CHECK(impostor.receive(1000).is_null());
  CHECK(server.server().stats().sessions_opened == before.sessions_opened);
}

TEST_CASE("server: a client with the wrong server key gets an error, not a hang", "[remote][server]") {
  Scratch dir("curve_wrong_server");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  RemoteEnvConfig link = keys.link(server.endpoint());
  link.server_key = remote::write_key_files(dir.path.string(), "not_the_server", remote::generate_curve_keys())[0];
  link.remote_timeout = 10;
  CHECK_THROWS_WITH(connect_remote_env(link, default_env_config("cartpole")), Contains("is server_key the server's public key?"));
  CHECK(server.server().stats().sessions_opened == 0);
}

TEST_CASE("server: a client whose server goes away gets an error at once, not after the timeout", "[remote][server]") {
  auto server = std::make_unique<ServerThread>(plain_options());
  RemoteEnvConfig link;
  link.remote = server->endpoint();
  link.remote_timeout = 30;
  const auto env = connect_remote_env(link, default_env_config("cartpole"));
  env->reset(1);
  server.reset();
  const auto t0 = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(env->step(Action::discrete(0)), Contains("the connection to the server was lost"));
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10));
}

TEST_CASE("server: plain text only with --insecure and only on loopback", "[remote][server]") {
  remote::ServerOptions o;
  o.bind = "tcp://0.0.0.0:*";
  o.insecure = true;
  CHECK_THROWS_WITH(remote::Server(o), Contains("plain text (--insecure) is allowed only on a loopback address"));
  o.bind = "tcp://192.168.1.10:7777";
  CHECK_THROWS_WITH(remote::Server(o), Contains("loopback"));
  o.bind = "tcp://127.0.0.1:*";
  o.insecure = false;
  CHECK_THROWS_WITH(remote::Server(o), Contains("give --keys DIR"));
  o.bind = "udp://127.0.0.1:7777";
  o.insecure = true;
  CHECK_THROWS_WITH(remote::Server(o), Contains("expected an address tcp://HOST:PORT"));
  o.bind = "tcp://127.0.0.1:*";
  remote::Server ok(o);
  CHECK_THAT(ok.endpoint(), Contains("tcp://127.0.0.1:"));
  // Nor can a client config ask for plain text to a remote host.
  nlohmann::json env = {{"name", "cartpole"}, {"remote", "tcp://10.0.0.5:7777"}};
  ConfigReader r(env, "c.json", "env");
  CHECK_THROWS_WITH(read_remote_env_config(r), Contains("c.json: env.server_key: needed for tcp://10.0.0.5:7777"));
}

TEST_CASE("server: numeric options outside a sane range are refused", "[remote][server]") {
  remote::ServerOptions o = plain_options();
  // Before: 1e-300 was accepted and closed every session before its first request.
  for (double bad : {1e-300, 0.5, -1.0, 1e300, std::numeric_limits<double>::quiet_NaN()}) {
    o.idle_timeout = bad;
    CHECK_THROWS_WITH(remote::Server(o), Contains("--idle-timeout: expected 1 to 604800 seconds"));
  }
  o.idle_timeout = 1.0;
  o.max_sessions = 5000;
  CHECK_THROWS_WITH(remote::Server(o), Contains("--max-sessions: expected 1 to 4096"));
  o.max_sessions = 1;
  CHECK_NOTHROW(remote::Server(o));
}

TEST_CASE("server: tcp://localhost binds the loopback address", "[remote][server]") {
  remote::ServerOptions o = plain_options();
  o.bind = "tcp://localhost:*";  // before: "No such device"
  ServerThread server(o);
  CHECK_THAT(server.endpoint(), Contains("tcp://127.0.0.1:"));
  RawClient client(server.endpoint());
  CHECK(client.call(hello_jaka)["reply"] == "hello");
}

TEST_CASE("server: under CurveZMQ a request of exactly 64 KiB is served", "[remote][server]") {
  Scratch dir("curve_boundary");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  RawClient client(server.endpoint(), zmq::socket_type::dealer, [&](zmq::socket_t& s) {
    s.set(zmq::sockopt::curve_serverkey, keys.server.public_key);
    s.set(zmq::sockopt::curve_publickey, keys.client.public_key);
    s.set(zmq::sockopt::curve_secretkey, keys.client.secret_key);
  });
  CHECK(client.call(hello_jaka)["reply"] == "hello");
  // Before: 65,504 to 65,536 bytes got no reply and lost the session (the limit counted the
  // encryption's 33 bytes).
  for (std::size_t size : {remote::max_request_frame_bytes - 40, remote::max_request_frame_bytes - 32,
                           remote::max_request_frame_bytes}) {
    std::string request = R"({"id": 4, "request": "state"})";
    request.resize(size, ' ');
    INFO(size);
    CHECK(client.call(request)["reply"] == "state");
  }
  std::string over = R"({"id": 5, "request": "state"})";
  over.resize(remote::max_request_frame_bytes + 1, ' ');
  const nlohmann::json refused = client.call(over);
  CHECK((refused.is_null() || refused.contains("error")));  // over the limit: never served
  CHECK(server.server().stats().sessions_opened == 1);
}

TEST_CASE("server: sessions end on close, on disconnect, after the idle timeout, the cap holds", "[remote][server]") {
  remote::ServerOptions o = plain_options();
  // Long enough that a loaded machine (CI's two cores under the sanitizers) never idles out the
  // sessions the test is still using, short enough to wait for once.
  o.idle_timeout = 2.0;
  o.max_sessions = 2;
  ServerThread server(o);
  RemoteEnvConfig link;
  link.remote = server.endpoint();
  {
    const auto env = connect_remote_env(link, default_env_config("cartpole"));
    CHECK(server.server().stats().sessions == 1);
  }  // close
  CHECK(eventually([&] { return server.server().stats().sessions == 0; }));
  // The close request, or the connection ending right after it, whichever the server sees first.
  CHECK_THAT(server.log(), Contains("closed (the client closed it)") || Contains("closed (the client disconnected) after 0 steps"));
  {
    // A client that vanishes mid-episode without a word.
    RawClient raw(server.endpoint());
    CHECK(raw.call(hello_jaka)["reply"] == "hello");
    CHECK(raw.call(R"({"id": 2, "request": "reset"})")["reply"] == "reset");
    CHECK(raw.call(R"({"id": 3, "request": "step", "action": 2})")["reply"] == "step");
    CHECK(server.server().stats().sessions == 1);
  }
  CHECK(eventually([&] { return server.server().stats().sessions == 0; }));
  CHECK_THAT(server.log(), Contains("closed (the client disconnected) after 1 steps"));
  // Idle.
  RawClient idle(server.endpoint());
  CHECK(idle.call(hello_jaka)["reply"] == "hello");
  CHECK(eventually([&] { return server.server().stats().sessions == 0; }, 10.0));
  CHECK_THAT(server.log(), Contains("closed (idle timeout)"));
  CHECK_THAT(idle.call(R"({"id": 5, "request": "reset"})")["error"].get<std::string>(),
             Contains("reset: no session on this connection: send hello first"));
  // The cap.
  RawClient a(server.endpoint()), b(server.endpoint()), c(server.endpoint());
  CHECK(a.call(hello_jaka)["reply"] == "hello");
  CHECK(b.call(hello_jaka)["reply"] == "hello");
  CHECK_THAT(c.call(hello_jaka)["error"].get<std::string>(), Contains("the server is full (2 sessions"));
}

TEST_CASE("server: hostile frames get error replies or a dropped connection, others are served", "[remote][server]") {
  ServerThread server(plain_options());
  RawClient good(server.endpoint());
  CHECK(good.call(hello_jaka)["reply"] == "hello");
  RawClient bad(server.endpoint());
  CHECK(bad.call("\xff\x00garbage")["error"] == "header is not valid JSON");
  bad.send({"{}", "x", "y"});
  CHECK_THAT(bad.receive()["error"].get<std::string>(), Contains("3 frames"));
  bad.send(std::vector<std::string>(40, "{}"));
  CHECK_THAT(bad.receive()["error"].get<std::string>(), Contains("more than 16 frames"));
  CHECK(bad.call(R"({"id": 7, "request": "step", "action": 1})")["id"] == 7);
  // A frame above the size limit makes ZeroMQ drop the sender's connection: no reply.
  bad.send({std::string(remote::max_request_frame_bytes + 1, ' ')});
  CHECK(bad.receive(500).is_null());
  // The well-behaved client is still served.
  CHECK(good.call(R"({"id": 2, "request": "reset", "seed": 1})")["reply"] == "reset");
  CHECK(good.call(R"({"id": 3, "request": "step", "action": 0})")["reply"] == "step");
  // REQ clients (an empty delimiter frame first) get the delimiter back.
  RawClient req(server.endpoint(), zmq::socket_type::req);
  CHECK(req.call(R"({"id": 1, "request": "state"})")["error"].get<std::string>().find("send hello first") != std::string::npos);
}

TEST_CASE("server: error replies are logged with their session and counted by message (first contact, item 7)",
          "[remote][server]") {
  Scratch dir("error_kinds");
  TestKeys keys(dir);
  ServerThread server(curve_options(keys));
  const auto remote = connect_remote_env(keys.link(server.endpoint()), default_env_config("cartpole"));
  remote->reset(1);
  for (int k = 0; k < 3; ++k) CHECK_THROWS(remote->step(Action::discrete(7)));
  CHECK(eventually([&] { return server.server().stats().errors == 3; }));
  const remote::ServerStats s = server.server().stats();
  REQUIRE(s.error_kinds.size() == 1);
  CHECK(s.error_kinds.begin()->second == 3);
  CHECK_THAT(s.error_kinds.begin()->first, Contains("action"));
  CHECK_THAT(server.log(), Contains("error reply to session 1: " + s.error_kinds.begin()->first));
}
