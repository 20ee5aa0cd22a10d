#pragma once
// Counts every heap allocation of the process, for the "no allocation in a step" tests.
// Every allocation goes through malloc, calloc or realloc (operator new, Eigen's
// aligned_malloc, Simbody's containers), and glibc lets an executable interpose them.
// Include this header in exactly one source file of a test executable (it defines the
// three functions) and read dmbd::test::allocations() before and after the code under
// test. Under AddressSanitizer (which owns malloc) nothing is interposed: such tests
// skip with DMBD_SKIP_UNDER_ASAN() (sanitizer.hpp).
#include <atomic>
#include <cstdlib>

#include "sanitizer.hpp"

namespace dmbd::test {
inline std::atomic<long> g_allocations{0};
inline long allocations() { return g_allocations.load(); }
}  // namespace dmbd::test

#if !DMBD_ASAN
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t n) {
  ++dmbd::test::g_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t m) {
  ++dmbd::test::g_allocations;
  return __libc_calloc(n, m);
}
void* realloc(void* p, std::size_t n) {
  ++dmbd::test::g_allocations;
  return __libc_realloc(p, n);
}
}
#endif  // !DMBD_ASAN
