#include "send_message.hpp"

namespace rdsim::remote {

bool send_message(zmq::socket_t& socket, const Message& m, zmq::send_flags flags) {
  const std::string header = encode_header(m);
  const auto more = [&](std::size_t i) { return i < m.arrays.size() ? zmq::send_flags::sndmore : zmq::send_flags::none; };
  if (!socket.send(zmq::buffer(header), more(0) | flags)) return false;
  for (std::size_t i = 0; i < m.arrays.size(); ++i)
    if (!socket.send(zmq::buffer(m.arrays[i].bytes), more(i + 1) | flags)) return false;
  return true;
}

}  // namespace rdsim::remote
