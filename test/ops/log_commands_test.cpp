// tiller-log's commands as library logic: wait (logtools/field_wait.hpp) meets after the value
// has held for hold_s, restarts the hold when the value changes, times out with the last value,
// prints progress every 10 s; csv refuses a --fields name that chooses nothing and lists the
// channel's fields; fields prints each field of the first message; restamp (shift_times) moves
// event times and every Tiller message's utime, and nothing else.
#include <gtest/gtest.h>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>

#include <sstream>

#include "logtools/field_wait.hpp"
#include "logtools/log_commands.hpp"

namespace tiller::logtools {
namespace {

std::vector<std::uint8_t> progress(bool complete, double distance) {
  path_progress_t p{};
  p.complete = complete;
  p.distance_to_goal = distance;
  std::vector<std::uint8_t> b(static_cast<std::size_t>(p.getEncodedSize()));
  p.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

constexpr TimeUs kS = kUsPerSecond;

TEST(FieldWait, MeetsAfterTheHoldAndRestartsWhenTheValueChanges) {
  FieldWait w({"TILLER_PATH_PROGRESS", "complete", "1", 5.0, 60.0}, 0);
  EXPECT_EQ(w.start_line(),
            "tiller-log: waiting for TILLER_PATH_PROGRESS.complete == 1, then 5 s more (time "
            "limit 60 s)\n");
  auto b = progress(true, 0.5);
  w.on_message(b.data(), b.size(), 10 * kS);
  EXPECT_EQ(w.verdict(14 * kS), FieldWait::Verdict::kWaiting);
  b = progress(false, 3.0);  // the value changes: the hold starts again
  w.on_message(b.data(), b.size(), 14 * kS);
  b = progress(true, 0.2);
  w.on_message(b.data(), b.size(), 16 * kS);
  EXPECT_EQ(w.verdict(20 * kS), FieldWait::Verdict::kWaiting);
  EXPECT_EQ(w.verdict(21 * kS), FieldWait::Verdict::kMet);
  EXPECT_EQ(w.verdict_line(21 * kS),
            "tiller-log: TILLER_PATH_PROGRESS.complete == 1 after 16.0 s (held 5.0 s)\n");
  const std::uint8_t junk[3] = {1, 2, 3};
  w.on_message(junk, sizeof junk, 21 * kS);  // ignored
  EXPECT_EQ(w.verdict(21 * kS), FieldWait::Verdict::kMet);
}

TEST(FieldWait, TimesOutWithTheLastValueAndPrintsProgressEveryTenSeconds) {
  FieldWait w({"TILLER_PATH_PROGRESS", "complete", "1", 0.0, 30.0}, 0);
  EXPECT_EQ(w.progress_line(9 * kS), std::nullopt);
  EXPECT_EQ(*w.progress_line(10 * kS), "tiller-log: 10 s: nothing on TILLER_PATH_PROGRESS yet\n");
  const auto b = progress(false, 12.5);
  w.on_message(b.data(), b.size(), 11 * kS);
  EXPECT_EQ(w.progress_line(15 * kS), std::nullopt);
  EXPECT_EQ(*w.progress_line(20 * kS),
            "tiller-log: 20 s: segment=0 n_waypoints=0 distance_to_goal=12.5 cross_track_error=0 "
            "complete=0\n");
  EXPECT_EQ(w.verdict(29 * kS), FieldWait::Verdict::kWaiting);
  EXPECT_EQ(w.verdict(30 * kS), FieldWait::Verdict::kTimedOut);
  EXPECT_EQ(w.verdict_line(30 * kS),
            "tiller-log: FAILED: TILLER_PATH_PROGRESS.complete never == 1 for 0 s within 30 s (1 "
            "messages; last complete = 0)\n");
}

TEST(LogCommands, CsvRefusesAnUnknownFieldAndFieldsListsTheFirstMessage) {
  const auto b = progress(true, 2.0);
  const std::vector<Event> events{{"TILLER_PATH_PROGRESS", 1'000'000, b},
                                  {"TILLER_PATH_PROGRESS", 1'500'000, b}};
  std::ostringstream out, err;
  EXPECT_EQ(
      export_csv(events, "TILLER_PATH_PROGRESS", {"distance_to_goal", "speed"}, 0, "", out, err),
      2);
  EXPECT_NE(err.str().find("tiller-log: --fields: no field \"speed\" in TILLER_PATH_PROGRESS "
                           "(path_progress_t); its fields: utime, path_id"),
            std::string::npos)
      << err.str();
  out.str("");
  EXPECT_EQ(export_csv(events, "TILLER_PATH_PROGRESS", {"distance_to_goal"}, 500'000, "", out, err),
            0);
  EXPECT_EQ(out.str(), "t_s,distance_to_goal\n0.500000,2\n1.000000,2\n");
  out.str("");
  EXPECT_EQ(print_fields(events, "TILLER_PATH_PROGRESS", out, err), 0);
  EXPECT_EQ(out.str().rfind("TILLER_PATH_PROGRESS: path_progress_t\n  utime = 0\n", 0), 0u)
      << out.str();
  EXPECT_NE(out.str().find("  distance_to_goal = 2\n"), std::string::npos);
}

TEST(Restamp, ShiftsEventTimesAndTillerUtimesOnly) {
  odometry_t o{};
  o.utime = 1'000'000;
  o.position[0] = 12.5;
  std::vector<Event> events{
      encode("TILLER_ODOMETRY", 1'000'100, o),
      {"OTHER", 1'000'200, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16}}};
  const std::vector<std::uint8_t> other = events[1].data;
  const TimeUs shift = 1'764'000'000'000'000 - 1'000'100;  // the log starts "now"
  EXPECT_EQ(shift_times(events, shift), 1u);
  EXPECT_EQ(events[0].time, 1'764'000'000'000'000);
  EXPECT_EQ(events[1].time, 1'764'000'000'000'100);
  odometry_t back{};
  ASSERT_TRUE(decode(events[0], back));
  EXPECT_EQ(back.utime, 1'000'000 + shift);
  EXPECT_EQ(back.position[0], 12.5);
  EXPECT_EQ(events[1].data, other);  // not a Tiller type: its bytes are kept
}

}  // namespace
}  // namespace tiller::logtools
