#pragma once
#include <zmq.hpp>

#include "rdsim/remote/message.hpp"

// Sends one protocol message on a ZeroMQ socket (private to the remote library): the header
// frame, then each array's bytes taken from the Message itself (one copy, into ZeroMQ's frame).
namespace rdsim::remote {

// `flags` is added to every frame (dontwait for a ROUTER); frames after the first carry sndmore
// as needed. Returns false when ZeroMQ did not take a frame (EAGAIN with dontwait).
bool send_message(zmq::socket_t& socket, const Message& m, zmq::send_flags flags);

}  // namespace rdsim::remote
