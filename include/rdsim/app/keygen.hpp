#pragma once
#include <string>

// `rdsim keygen NAME`: a CurveZMQ key pair for `rdsim serve` and its clients (src/app/keygen.cpp;
// file formats in remote/curve_keys.hpp).
namespace rdsim {

struct KeygenOptions {
  std::string name;
  std::string dir = ".";
};

int keygen_command(const KeygenOptions& options);

}  // namespace rdsim
