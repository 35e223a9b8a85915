#pragma once
#include <string>

// Optional capability of an Env (implemented next to rdsim::Env by envs that can do it): its
// complete state (physics, step counter, random generator) as bytes. A resumed training run
// continues bit-identically only when every env offers this; see VecEnv::load.
namespace rdsim {

class EnvState {
public:
  virtual ~EnvState() = default;
  virtual std::string save_state() const = 0;
  // Throws rdsim::Error naming `source` when the bytes are not a state of this env.
  virtual void load_state(const std::string& bytes, const std::string& source) = 0;
};

}  // namespace rdsim
