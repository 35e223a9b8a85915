#pragma once
// Shared by the test programs: the message a call fails with.
#include <functional>
#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim::test {

// The message of the rdsim::Error that `f` throws, or "(no error)" when it returns.
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace rdsim::test
