// Heap allocation counting for the tests and benchmarks that check a hot path allocates nothing.
// A target gets it by linking tiller_alloc_count (test/common/CMakeLists.txt; tiller_test and
// tiller_benchmark take ALLOC_COUNT): alloc_count.cpp replaces the global operator new for the
// whole binary. Read the count before and after the code under test and compare.
#pragma once

namespace tiller::test {

// Calls of the global operator new (plain and aligned; the array forms reach them through the
// standard library's defaults) in this process so far, from every thread.
long allocations();

}  // namespace tiller::test
