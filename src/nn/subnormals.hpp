#pragma once
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define RDSIM_HAVE_MXCSR 1
#endif

// Subnormal floats (below 1.2e-38) take a slow path through x86 CPUs' float units (a hundred
// cycles and more per operation). A pass whose subnormal values do not matter can flush them to
// zero on this thread for its lifetime (MXCSR's FTZ and DAZ bits), restored afterwards.
namespace rdsim::nn::subnormals {

class FlushToZero {
public:
#ifdef RDSIM_HAVE_MXCSR
  FlushToZero() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~FlushToZero() { _mm_setcsr(saved_); }
#else
  FlushToZero() = default;
#endif
  FlushToZero(const FlushToZero&) = delete;
  FlushToZero& operator=(const FlushToZero&) = delete;

private:
#ifdef RDSIM_HAVE_MXCSR
  static constexpr unsigned kFlushToZero = 0x8000, kDenormalsAreZero = 0x0040;
  unsigned saved_;
#endif
};

}  // namespace rdsim::nn::subnormals
