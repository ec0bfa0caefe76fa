// SPDX-License-Identifier: GPL-3.0-or-later
// The tests' main: GoogleTest's, plus the leak check run here rather than at exit under ASan.
//
// LeakSanitizer's own check runs from an atexit handler, while the static destructors of the
// system libraries (OpenEXR's IlmThread pool, log4cplus's pool via OpenVDB, oneTBB's workers,
// Mesa's disk-cache thread) are tearing down their threads. A thread that exits while LSan stops
// the world makes the tracer fault ("Tracer caught signal 11 ... LeakSanitizer has encountered a
// fatal error"): a test that passed then fails at random (seen in CI on
// TsisGpu.OccludedEnvironmentOnAConvexBodyMatchesItsShIrradiance, about one run in three). Here,
// every one of those threads is still parked on its condition variable, and the check at exit is
// skipped once it has run: the same leaks are found, without the race.
#include <gtest/gtest.h>

#if defined(__SANITIZE_ADDRESS__)
#define TRANSLUCENT_HAS_LSAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TRANSLUCENT_HAS_LSAN 1
#endif
#endif
#ifdef TRANSLUCENT_HAS_LSAN
#include <sanitizer/lsan_interface.h>
#endif

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
#ifdef TRANSLUCENT_HAS_LSAN
  __lsan_do_leak_check();  // exits with LSan's error code when it finds a leak
#endif
  return result;
}
