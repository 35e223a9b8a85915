// `rdsim keygen NAME`: writes DIR/NAME.key (public) and DIR/NAME.key_secret (secret, mode 0600).
#include "rdsim/app/keygen.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/remote/curve_keys.hpp"

namespace rdsim {

int keygen_command(const KeygenOptions& o) {
  const std::vector<std::string> paths = remote::write_key_files(o.dir, o.name, remote::generate_curve_keys());
  std::printf("rdsim keygen: wrote %s (public key: give it to the other side; a server's clients go in its "
              "--keys DIR/clients/)\n              and %s (secret key, mode 0600: keep it here)\n",
              paths[0].c_str(), paths[1].c_str());
  return 0;
}

Command keygen_command_entry() {
  return {"keygen", "Write a CurveZMQ key pair: DIR/NAME.key (public) and DIR/NAME.key_secret (secret, mode 0600)",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<KeygenOptions>();
            cmd.add_option("name", o->name, "Key name (letters, digits, _ - .)")->required();
            cmd.add_option("--dir", o->dir, "Folder to write the two files to")->capture_default_str();
            return [o] { return keygen_command(*o); };
          }};
}

}  // namespace rdsim
