#include "spin_wait.hpp"

#include <thread>

namespace rdsim::remote {

void spin_until_readable(zmq::socket_t& socket, std::chrono::microseconds limit) {
  using Clock = std::chrono::steady_clock;
  const auto until = Clock::now() + limit;
  do {
    if (socket.get(zmq::sockopt::events) & ZMQ_POLLIN) return;
    std::this_thread::yield();
  } while (Clock::now() < until);
}

}  // namespace rdsim::remote
