#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// A client's request, read from its frames by one pure function (bytes in, typed request or
// error out: no sockets, no env, no state), so it can be unit-tested and fuzzed on its own
// (tests/fuzz/fuzz_request.cpp). The requests and their keys are docs/protocol.md's.
namespace rdsim::remote {

enum class RequestKind { Hello, Reset, Step, Position, Joints, Cameras, State, DropCaches, Close };

const char* to_string(RequestKind kind);

struct Request {
  long long id = 0;  // echoed in the reply
  RequestKind kind = RequestKind::Hello;
  // hello
  int protocol = 0;
  nlohmann::json env;  // the "env" object, as in a training config
  // reset
  std::optional<std::uint64_t> seed;
  // step: an integer for Discrete action spaces, a list of numbers for Box ones
  std::optional<int> action_index;
  std::vector<float> action_values;
  // position: the effector target (world frame, m)
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  // joints: one target per joint
  std::vector<float> joints;
  // cameras: image size and which cameras (empty: all)
  int width = 0, height = 0;
  std::vector<std::string> cameras;
};

struct ParsedRequest {
  std::optional<Request> request;  // when the request is well-formed
  nlohmann::json id;               // its id when one could be read (for the error reply), else null
  std::string error;               // why it is not
};

// `frames`: the message's parts after the routing envelope. Checks sizes, depth and types
// (protocol.hpp's limits); what depends on the session's env (action range, joint count, camera
// names) is checked by the Session.
ParsedRequest parse_request(const std::vector<std::string_view>& frames);

}  // namespace rdsim::remote
