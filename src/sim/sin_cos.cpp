#include "sin_cos.hpp"

#include <cmath>

namespace rdsim {

void sin_cos(const double* angles, double* sines, double* cosines, int n) {
#pragma omp simd
  for (int i = 0; i < n; ++i) {
    sines[i] = std::sin(angles[i]);
    cosines[i] = std::cos(angles[i]);
  }
}

}  // namespace rdsim
