#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// `rdsim envs`: lists the registered environments (src/app/envs.cpp).
namespace rdsim {

int envs_command();

}  // namespace rdsim
