#pragma once
#include <zmq.hpp>

#include <chrono>
#include <string>

#include "rdsim/remote/message.hpp"
#include "rdsim/remote/remote_env_config.hpp"

// The client end of one connection to an `rdsim serve` (private to the remote library): a
// ZeroMQ DEALER socket, CurveZMQ client keys, request ids and the wait for each reply.
namespace rdsim::remote {

class RemoteLink {
public:
  // Loads the key files and connects (ZeroMQ connects in the background: a wrong address, an
  // absent server (within a few seconds) or a refused key shows at the first call).
  explicit RemoteLink(const RemoteEnvConfig& config);
  ~RemoteLink();

  // Sends `request` (its "id" is set here) and returns the reply with that id. rdsim::Error with
  // the server's message for an error reply, when the server refuses this client's key, or when no
  // reply comes within the timeout.
  Message call(Message request);
  // call() in two halves, so several links can have a request in flight at once: send_request
  // returns the id that wait_reply(id) then waits for (with call()'s errors and timeout).
  long long send_request(Message request);
  Message wait_reply(long long id);
  // Sends `request` without waiting for its reply (close at exit).
  void post(Message request);

  const std::string& endpoint() const { return endpoint_; }

private:
  void send(Message& request);
  void check_monitor();

  std::string endpoint_;
  double timeout_;
  std::chrono::steady_clock::time_point connect_deadline_;  // report an absent server after this
  zmq::socket_t socket_;
  zmq::socket_t monitor_;
  long long next_id_ = 1;
  bool curve_ = false;
  bool replied_ = false;  // a reply came on this connection
  bool connected_ = false;  // the TCP connection is up (a monitor event)
  bool refused_ = false;    // a connection attempt failed and is retried (nothing listens there)
};

}  // namespace rdsim::remote
