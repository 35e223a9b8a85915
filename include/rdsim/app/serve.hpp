#pragma once
#include <string>

// `rdsim serve`: hosts environments for remote clients (src/app/serve.cpp; the engine is
// remote/server.hpp, the protocol docs/protocol.md).
namespace rdsim {

struct ServeOptions {
  std::string bind = "tcp://127.0.0.1:7777";  // port * picks a free one (printed on start)
  // DIR/server.key_secret (the server's pair) and DIR/clients/*.key (the public keys of the clients
  // allowed in). Empty: plain text, only with `insecure` on a loopback address.
  std::string keys_dir;
  bool insecure = false;
  int max_sessions = 16;
  double idle_timeout = 300.0;  // s
};

// Serves until SIGINT or SIGTERM. Prints "rdsim serve: listening on ADDRESS ..." on stdout first.
int serve_command(const ServeOptions& options);

}  // namespace rdsim
