#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// `rdsim envs`: lists the registered environments; with a training config, that config's env
// with every option resolved and its spaces (src/app/envs.cpp).
namespace rdsim {

int envs_command(const std::string& config_path = "");

}  // namespace rdsim
