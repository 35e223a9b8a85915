#pragma once
// Sines and cosines of a batch of angles at once; only src/sim includes this.
//
// Why: the null-space IK turns every joint of its chain 20 times per env step, and a scalar
// sin/cos pair (glibc's sincos) cost about as much as the rest of the chain's kinematics. This
// file is compiled so that GCC vectorises the loop through glibc's libmvec (8 or 4 angles per
// call, within 4 ulp of the exact values); elsewhere it is the plain loop.
namespace rdsim {

// sines[i] = sin(angles[i]), cosines[i] = cos(angles[i]) for i < n (angles in rad).
void sin_cos(const double* angles, double* sines, double* cosines, int n);

}  // namespace rdsim
