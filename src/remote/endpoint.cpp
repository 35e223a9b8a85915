#include "rdsim/remote/endpoint.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim::remote {
namespace {

// HOST of tcp://HOST:PORT ("" when not that form); brackets of [::1] removed.
std::string host_of(const std::string& endpoint, std::string* port = nullptr) {
  const std::string scheme = "tcp://";
  if (endpoint.rfind(scheme, 0) != 0) return "";
  const std::string rest = endpoint.substr(scheme.size());
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0) return "";
  if (port) *port = rest.substr(colon + 1);
  std::string host = rest.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return host;
}

}  // namespace

bool is_loopback_endpoint(const std::string& endpoint) {
  const std::string host = host_of(endpoint);
  if (host == "localhost" || host == "::1") return true;
  // 127.0.0.0/8, written as four decimal numbers.
  if (host.rfind("127.", 0) != 0) return false;
  int parts = 0;
  std::size_t at = 0;
  while (at <= host.size()) {
    const std::size_t dot = std::min(host.find('.', at), host.size());
    const std::string part = host.substr(at, dot - at);
    if (part.empty() || part.size() > 3 || part.find_first_not_of("0123456789") != std::string::npos || std::stoi(part) > 255)
      return false;
    ++parts;
    at = dot + 1;
  }
  return parts == 4;
}

std::string bindable_endpoint(const std::string& endpoint) {
  std::string port;
  const std::string host = host_of(endpoint, &port);
  return host == "localhost" ? "tcp://127.0.0.1:" + port : endpoint;
}

bool is_ipv6_endpoint(const std::string& endpoint) { return host_of(endpoint).find(':') != std::string::npos; }

void check_tcp_endpoint(const std::string& endpoint, const std::string& what) {
  std::string port;
  const std::string host = host_of(endpoint, &port);
  const bool port_ok = port == "*" || (!port.empty() && port.size() <= 5 &&
                                       port.find_first_not_of("0123456789") == std::string::npos && std::stoi(port) <= 65535);
  if (host.empty() || !port_ok)
    throw Error(what + ": expected an address tcp://HOST:PORT (e.g. tcp://127.0.0.1:7777), got \"" + endpoint + "\"");
}

}  // namespace rdsim::remote
