// Freshness (core/time.hpp): an input is fresh when both its receive time and its own utime (the
// sender's clock) are within the limit, the utime with the clock offset bound on top; a message
// already too old by its utime, or ahead of the receiver's clock by more than the bound, is
// refused on arrival and refreshes nothing. Hand-computed cases with limit 0.5 s and the default
// bound 0.25 s unless said (times in us).
#include <gtest/gtest.h>

#include <cstdint>

#include "core/time.hpp"

namespace tiller {
namespace {

constexpr TimeUs kLimit = 500'000;
constexpr TimeUs kNow = 100'000'000;  // 100 s

TEST(Freshness, TheDefaultClockOffsetBoundIsAQuarterSecond) {
  EXPECT_EQ(kDefaultClockOffsetUs, 250'000);
}

TEST(Freshness, ArrivalEdgesAreExact) {
  // Old: now - utime > limit + bound = 750 ms.
  EXPECT_EQ(arrival_of(kNow, kNow - 750'000, kLimit, 250'000), Arrival::kAccepted);
  EXPECT_EQ(arrival_of(kNow, kNow - 750'001, kLimit, 250'000), Arrival::kStale);
  // Future: utime - now > bound = 250 ms.
  EXPECT_EQ(arrival_of(kNow, kNow + 250'000, kLimit, 250'000), Arrival::kAccepted);
  EXPECT_EQ(arrival_of(kNow, kNow + 250'001, kLimit, 250'000), Arrival::kFuture);
  // A bound of 0 (one computer): the utime may be neither ahead nor older than the limit.
  EXPECT_EQ(arrival_of(kNow, kNow, kLimit, 0), Arrival::kAccepted);
  EXPECT_EQ(arrival_of(kNow, kNow + 1, kLimit, 0), Arrival::kFuture);
  EXPECT_EQ(arrival_of(kNow, kNow - 500'000, kLimit, 0), Arrival::kAccepted);
  EXPECT_EQ(arrival_of(kNow, kNow - 500'001, kLimit, 0), Arrival::kStale);
}

TEST(Freshness, ExtremeUtimesFromTheWireDoNotOverflow) {
  EXPECT_EQ(arrival_of(kNow, INT64_MIN, kLimit, 250'000), Arrival::kStale);
  EXPECT_EQ(arrival_of(kNow, INT64_MAX, kLimit, 250'000), Arrival::kFuture);
  EXPECT_EQ(arrival_of(kNow, 0, kLimit, 250'000), Arrival::kStale);  // a sender that never stamps
}

TEST(Freshness, AMessageStampedNowStaysFreshForTheLimitByItsReceiveTime) {
  Freshness f(kLimit);
  EXPECT_FALSE(f.fresh(kNow));
  EXPECT_EQ(f.mark(kNow, kNow), Arrival::kAccepted);
  EXPECT_TRUE(f.fresh(kNow));
  EXPECT_TRUE(f.fresh(kNow + 500'000));
  EXPECT_FALSE(f.fresh(kNow + 500'001));
  EXPECT_EQ(f.stale_events(), 1);
}

TEST(Freshness, ReceivedNowButOldByItsUtimeExpiresByItsUtime) {
  // Queued in a stopped process: 0.7 s old by its utime when it is received. Accepted (0.7 <=
  // 0.75), fresh until its utime is 0.75 s old, 50 ms later, although its receive time would
  // keep it for 0.5 s.
  Freshness f(kLimit);
  EXPECT_EQ(f.mark(kNow, kNow - 700'000), Arrival::kAccepted);
  EXPECT_TRUE(f.fresh(kNow));
  EXPECT_TRUE(f.fresh(kNow + 50'000));
  EXPECT_FALSE(f.fresh(kNow + 50'001));
  EXPECT_EQ(f.last_utime(), kNow - 700'000);
}

TEST(Freshness, AMessageTooOldByItsUtimeRefreshesNothing) {
  Freshness f(kLimit);
  ASSERT_EQ(f.mark(kNow, kNow), Arrival::kAccepted);
  // 4 s later a queued message arrives, stamped 3.9 s ago: refused; the input stays as it was
  // (last accepted at kNow, so stale now).
  const TimeUs later = kNow + 4'000'000;
  EXPECT_EQ(f.mark(later, later - 3'900'000), Arrival::kStale);
  EXPECT_EQ(f.last(), kNow);
  EXPECT_EQ(f.last_utime(), kNow);
  EXPECT_FALSE(f.fresh(later));
  // Never seen before: a refused message does not make it seen either.
  Freshness g(kLimit);
  EXPECT_EQ(g.mark(later, later - 3'900'000), Arrival::kStale);
  EXPECT_FALSE(g.ever());
  EXPECT_FALSE(g.fresh(later));
}

TEST(Freshness, AMessageFromTheFutureBeyondTheBoundIsRefused) {
  Freshness f(kLimit);
  EXPECT_EQ(f.mark(kNow, kNow + 300'000), Arrival::kFuture);
  EXPECT_FALSE(f.ever());
  // Within the bound: accepted, and fresh by its receive time for the limit (its utime is
  // ahead, so the utime rule gives it no more than the receive rule).
  EXPECT_EQ(f.mark(kNow, kNow + 200'000), Arrival::kAccepted);
  EXPECT_TRUE(f.fresh(kNow + 500'000));
  EXPECT_FALSE(f.fresh(kNow + 500'001));
}

TEST(Freshness, TheClockOffsetBoundIsTheOneGivenAtMark) {
  // A bound of 0.1 s: a 0.6 s old message is accepted (<= 0.6) and fresh for no time at all
  // after it; 0.6 s + 1 us is refused.
  Freshness f(kLimit);
  EXPECT_EQ(f.mark(kNow, kNow - 600'001, 100'000), Arrival::kStale);
  EXPECT_EQ(f.mark(kNow, kNow - 600'000, 100'000), Arrival::kAccepted);
  EXPECT_TRUE(f.fresh(kNow));
  EXPECT_FALSE(f.fresh(kNow + 1));
  // A bound of 1 s: the same message stays fresh until its receive time is 0.5 s old.
  Freshness g(kLimit);
  EXPECT_EQ(g.mark(kNow, kNow - 600'000, 1'000'000), Arrival::kAccepted);
  EXPECT_TRUE(g.fresh(kNow + 500'000));
  EXPECT_FALSE(g.fresh(kNow + 500'001));
}

TEST(Freshness, ResetMakesItAbsentUntilTheNextAcceptedMessage) {
  Freshness f(kLimit);
  ASSERT_EQ(f.mark(kNow, kNow), Arrival::kAccepted);
  f.reset();
  EXPECT_FALSE(f.fresh(kNow));
  ASSERT_EQ(f.mark(kNow + 10, kNow + 10), Arrival::kAccepted);
  EXPECT_TRUE(f.fresh(kNow + 10));
}

}  // namespace
}  // namespace tiller
