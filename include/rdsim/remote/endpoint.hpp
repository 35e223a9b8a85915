#pragma once
#include <string>

// ZeroMQ endpoints ("tcp://127.0.0.1:7777") as the server and the client check them.
namespace rdsim::remote {

// True for tcp:// addresses on the loopback interface only: 127.x.x.x, localhost, [::1].
// Plain text (no CurveZMQ) is allowed only there.
bool is_loopback_endpoint(const std::string& endpoint);

// What a server binds for `endpoint`: ZeroMQ binds an interface name or an address, and
// "localhost" is neither, so tcp://localhost:P binds tcp://127.0.0.1:P.
std::string bindable_endpoint(const std::string& endpoint);
// Whether the host is an IPv6 address ([::1]): the socket must then enable IPv6 (ZMQ_IPV6).
bool is_ipv6_endpoint(const std::string& endpoint);

// rdsim::Error unless `endpoint` is tcp://HOST:PORT (PORT a number, or * for a server to pick).
void check_tcp_endpoint(const std::string& endpoint, const std::string& what);

}  // namespace rdsim::remote
