// The replacement global allocation functions behind tiller::test::allocations(), in their own
// translation unit: GCC 12 warns -Wmismatched-new-delete where it inlines malloc/free behind
// operator new/delete next to standard containers. Built as an OBJECT library, so these
// definitions are always linked into the test binary (a static archive member nobody references
// by name would be left out). The array forms are not replaced: libstdc++'s operator new[] and
// delete[] call the ones below. The aligned forms are, because libstdc++'s aligned operator new
// calls aligned_alloc directly and would not be counted.
#include "alloc_count.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

long tiller::test::allocations() {
  return g_allocations.load(std::memory_order_relaxed);
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t al = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(al, (n + al - 1) / al * al)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
