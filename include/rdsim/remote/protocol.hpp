#pragma once
#include <cstddef>

// The rdsim remote-control protocol (docs/protocol.md): its version and the limits a server
// enforces on what it reads, so that no message can make it allocate much, recurse deeply or
// work long.
namespace rdsim::remote {

// Sent in `hello`; a server answers a different version with an error reply.
inline constexpr int protocol_version = 1;

// A larger frame makes ZeroMQ drop the sender's connection (ZMQ_MAXMSGSIZE): requests are small.
inline constexpr std::size_t max_request_frame_bytes = 64 * 1024;
// Replies carry images: a client accepts frames up to this size.
inline constexpr std::size_t max_reply_frame_bytes = 64 * 1024 * 1024;
// Parts of one message. Requests have one (the JSON header) after an optional empty delimiter.
inline constexpr int max_frames = 16;
// Nesting of JSON objects and arrays in a header.
inline constexpr int max_json_depth = 8;
// Elements of a vector in a request (joint targets: the InMoov has 54 joints).
inline constexpr int max_vector_size = 256;
// Largest magnitude of a number in a request vector (keeps every value a finite float).
inline constexpr double max_vector_value = 1e6;
// Side of a first-person camera image a client may ask for, in pixels.
inline constexpr int max_camera_side = 1024;
// Bytes of one observation a session's env may produce (raw pixels: height x width x channels).
inline constexpr std::size_t max_observation_bytes = 16 * 1024 * 1024;

}  // namespace rdsim::remote
