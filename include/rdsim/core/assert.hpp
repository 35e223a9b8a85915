#pragma once
#include <string>

// Programmer errors, kept apart from bad outside input.
//
//   rdsim::Error (core/error.hpp)  bad input from outside the program (a config, a URDF, a model
//                                  file, a network message, a driver that lacks a feature): thrown,
//                                  caught at the top, one clear message, exit code 1.
//   RDSIM_ASSERT(condition, what)  a broken promise between parts of rdsim itself (a caller
//                                  breaking a documented precondition): nothing sensible can
//                                  follow, so it prints "file:line: assertion `condition` failed:
//                                  what" and aborts (a core dump and a debugger stop right there).
//
// RDSIM_ASSERT is on in every build type (Release too), so keep its condition cheap: a compare, a
// size check. `what` is a const char* or std::string, evaluated only when the check fails.
namespace rdsim::detail {

[[noreturn]] void assertion_failed(const char* condition, const char* file, int line, const std::string& what);

}  // namespace rdsim::detail

#define RDSIM_ASSERT(condition, what)                                                \
  do {                                                                               \
    if (!(condition)) [[unlikely]]                                                   \
      ::rdsim::detail::assertion_failed(#condition, __FILE__, __LINE__, (what));     \
  } while (false)
