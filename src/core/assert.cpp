#include "rdsim/core/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace rdsim::detail {

void assertion_failed(const char* condition, const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "rdsim: internal error: %s:%d: assertion `%s` failed: %s\n", file, line, condition,
               what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace rdsim::detail
