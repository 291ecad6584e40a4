// operator new counting for count_guard_test, in its own translation unit (GCC 12 otherwise
// warns -Wmismatched-new-delete where it inlines the replacement next to standard containers).
#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> g_allocs{0};
}
void* operator new(std::size_t n) {
  ++g_allocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

long count_guard_test_allocations() {
  return g_allocs.load();
}
