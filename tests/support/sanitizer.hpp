#pragma once
// DMBD_ASAN is 1 when this test executable is built with AddressSanitizer
// (scripts/sanitize). AddressSanitizer owns malloc and free, so the tests that interpose
// the C allocator to count allocations (the renderer's, the plant step's) compile their
// interposer out and skip those tests there; the normal build runs them.
#if defined(__SANITIZE_ADDRESS__)
#define DMBD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DMBD_ASAN 1
#endif
#endif
#ifndef DMBD_ASAN
#define DMBD_ASAN 0
#endif

#define DMBD_SKIP_UNDER_ASAN()                                                                   \
  do {                                                                                           \
    if (DMBD_ASAN) GTEST_SKIP() << "counts allocations by interposing malloc: not under ASan"; \
  } while (0)
