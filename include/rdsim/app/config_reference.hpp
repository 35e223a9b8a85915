#pragma once
#include <string>

// `rdsim config-reference`: the reference of every training-config key, as markdown tables built
// from the describe() tables next to each config struct (src/app/config_reference.cpp). Its
// output is docs/config.md; a test fails when the two differ, so the document cannot drift.
namespace rdsim {

// The whole document (docs/config.md).
std::string config_reference();

// Prints config_reference() to stdout.
int config_reference_command();

}  // namespace rdsim
