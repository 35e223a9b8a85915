// The environment prefix for child processes whose leak reports the sanitizer build cannot judge.
//
// Under AddressSanitizer (the sanitizer CI build, .ci/run), two kinds of system code leave leak
// reports whose only stack frames have no module name, so no rule in tests/sanitizers/lsan.supp
// can name them: Mesa llvmpipe's JIT-compiled shader code (the teleop window's OpenGL on Xvfb),
// and Open MPI's plugins, which it unloads at MPI_Finalize (Debian's Open MPI 4.1 has no switch to
// keep them). Those children run without the leak check; every other ASan/UBSan check stays on,
// and the rdsim code they run is leak-checked by the in-process tests of its library.
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RDSIM_TEST_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define RDSIM_TEST_UNDER_ASAN 1
#endif

namespace rltest {
#ifdef RDSIM_TEST_UNDER_ASAN
inline constexpr const char* no_leak_check_env = "ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 ";
#else
inline constexpr const char* no_leak_check_env = "";
#endif
}  // namespace rltest
