// Counts heap allocations in this binary (global operator new replaced): for the tests and
// benchmarks that check that an ESC cycle allocates nothing. Include in exactly one file.
#pragma once
// GCC sees malloc behind operator new and free behind operator delete once they inline, and
// calls that a mismatch; here they are the same pair by construction.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <atomic>
#include <cstdlib>
#include <new>

namespace tiller::test {
inline std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  tiller::test::g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
