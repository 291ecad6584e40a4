// The cost of message signing per message: Signer::sign (the publishing side) and
// Verifier::check (the receiving side: key id, MAC, replay window), and the two together, for a
// 6-thruster
// TILLER_THRUSTER_COMMAND-sized payload and a 1 kB one; the "allocs" counter is heap
// allocations per iteration (0 on the hot path). Run: build/bench/auth_bench
#include <benchmark/benchmark.h>

#include <cstring>
#include <vector>

#include "../common/alloc_count.hpp"
#include "auth/trailer.hpp"
#include "auth/verifier.hpp"

namespace {

using namespace tiller;
using namespace tiller::auth;

constexpr TimeUs kT0 = 1'764'000'000'000'000;

Key bench_key() {
  Key k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(i);
  k.id = key_id(k.bytes);
  return k;
}

void BM_Sign(benchmark::State& state) {
  const auto n = static_cast<int>(state.range(0));
  Signer s(bench_key(), "mixer");
  std::vector<std::uint8_t> pkt(static_cast<std::size_t>(n + kTrailerSize), 0x5a);
  TimeUs t = kT0;
  const long before = test::allocations();
  for (auto _ : state) {
    s.sign("TILLER_THRUSTER_COMMAND", pkt.data(), n, ++t, pkt.data() + n);
    benchmark::DoNotOptimize(pkt.data());
  }
  state.counters["allocs"] = benchmark::Counter(static_cast<double>(test::allocations() - before) /
                                                static_cast<double>(state.iterations()));
}

// Sign then check, a new stamp each time (every message accepted, the stream state updated):
// what one message costs its publisher and one receiver together.
void BM_SignThenVerify(benchmark::State& state) {
  const auto n = static_cast<int>(state.range(0));
  const Key k = bench_key();
  Signer s(k, "mixer");
  Policy p;
  p.key = k;
  p.require_signed = true;
  Verifier v(p);
  std::vector<std::uint8_t> pkt(static_cast<std::size_t>(n + kTrailerSize), 0x5a);
  TimeUs t = kT0;
  long long refused = 0;
  const long before = test::allocations();
  for (auto _ : state) {
    s.sign("TILLER_THRUSTER_COMMAND", pkt.data(), n, ++t, pkt.data() + n);
    const Checked c =
        v.check("TILLER_THRUSTER_COMMAND", pkt.data(), static_cast<int>(pkt.size()), t);
    refused += c.verdict != Verdict::kSigned;
    benchmark::DoNotOptimize(c);
  }
  state.counters["allocs"] = benchmark::Counter(static_cast<double>(test::allocations() - before) /
                                                static_cast<double>(state.iterations()));
  state.counters["refused"] = static_cast<double>(refused);
}

// The check alone, without the pool's pause/resume overhead: the same packet checked again is a
// replay, refused after the full MAC (the same work as an accepted one).
void BM_VerifyMacOnly(benchmark::State& state) {
  const auto n = static_cast<int>(state.range(0));
  const Key k = bench_key();
  Signer s(k, "mixer");
  Policy p;
  p.key = k;
  p.require_signed = true;
  Verifier v(p);
  std::vector<std::uint8_t> pkt(static_cast<std::size_t>(n + kTrailerSize), 0x5a);
  s.sign("TILLER_THRUSTER_COMMAND", pkt.data(), n, kT0, pkt.data() + n);
  v.check("TILLER_THRUSTER_COMMAND", pkt.data(), static_cast<int>(pkt.size()), kT0);
  const long before = test::allocations();
  for (auto _ : state) {
    const Checked c =
        v.check("TILLER_THRUSTER_COMMAND", pkt.data(), static_cast<int>(pkt.size()), kT0);
    benchmark::DoNotOptimize(c);
  }
  state.counters["allocs"] = benchmark::Counter(static_cast<double>(test::allocations() - before) /
                                                static_cast<double>(state.iterations()));
}

BENCHMARK(BM_Sign)->Arg(120)->Arg(1024);
BENCHMARK(BM_VerifyMacOnly)->Arg(120)->Arg(1024);
BENCHMARK(BM_SignThenVerify)->Arg(120)->Arg(1024);

}  // namespace

BENCHMARK_MAIN();
