// tiller-log: looks inside an LCM log.
//   tiller-log summary LOG                      channels, types, counts, rates, gaps; per process
//                                               its last heartbeat and non-zero drop counters
//   tiller-log csv LOG CHANNEL [--fields F,..] [--output FILE]
//                                               one CSV row per message, fields decoded by name
//   tiller-log fields LOG CHANNEL               the field paths of a channel's first message
//   tiller-log restamp LOG OUT                  LOG moved in time to start now (event times and
//                                               every message's utime), for lcm-logplayer
//   tiller-log wait CHANNEL FIELD VALUE [--hold-s S] [--timeout-s S] [--mission FILE]
//                                               live: exits 0 once FIELD of CHANNEL has equalled
//                                               VALUE for S seconds, 1 after the timeout (a
//                                               launch file's ends_with process: "mission done")
// The commands are logtools/logsummary.hpp, log_commands.hpp and field_wait.hpp.
#include <iostream>

#include "logtools/field_wait.hpp"
#include "logtools/log_commands.hpp"
#include "logtools/log_io.hpp"
#include "logtools/logsummary.hpp"
#include "mission/mission.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

using namespace tiller;

namespace {
// wait's hold and timeout: the options, else the mission file's, else 0 s and 600 s.
logtools::WaitSpec wait_spec(const app::Args& a) {
  const auto& p = a.positional;
  logtools::WaitSpec w{p[1], p[2], p[3]};
  if (!a.get("mission").empty()) {
    const auto m = mission::load_mission_file(a.get("mission"));
    w.hold_s = m.station_keep_s;
    w.timeout_s = m.time_limit_s;
  }
  constexpr double kDay = 86400;
  if (!a.get("hold-s").empty())
    w.hold_s = app::number_option(a, "hold-s", 0, kDay, "a number of seconds from 0 to 86400");
  if (!a.get("timeout-s").empty())
    w.timeout_s =
        app::number_option(a, "timeout-s", 0, kDay, "a number of seconds from 0 to 86400");
  return w;
}
}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-log", [&] {
    app::Spec spec{
        "tiller-log",
        "Looks inside an LCM log: summary (channels, rates, gaps, each process's health and what\n"
        "needs attention), csv (one row per message, --fields, --output), fields (the field paths\n"
        "of a channel's first message); restamp (LOG moved to start now, utimes included, to play\n"
        "into live processes); wait (live, on --lcm-url): exit 0 once FIELD of CHANNEL has\n"
        "equalled VALUE for --hold-s, 1 after --timeout-s.",
        "",
        {{"fields", "F[,F..]", "fields to export (path or prefix: position, command, waypoints[0])",
          ""},
         {"output", "FILE", "write the CSV here instead of standard output", ""},
         {"hold-s", "S",
          "wait: the value must hold this long, s, 0..86400 (default: the mission's "
          "station_keep_s, else 0)",
          ""},
         {"timeout-s", "S",
          "wait: give up (exit 1) after this long, s, 0..86400 (default: the mission's "
          "time_limit_s, else 600)",
          ""},
         {"mission", "FILE", "wait: take hold and timeout from this mission file", ""}},
        false};  // no config file: --config refused (--lcm-url is for wait)
    spec.arguments =
        "summary LOG | csv LOG CHANNEL | fields LOG CHANNEL | restamp LOG OUT | wait CHANNEL "
        "FIELD VALUE";
    spec.commands = {{"summary", 1}, {"csv", 2}, {"fields", 2}, {"restamp", 2}, {"wait", 3}};
    const app::Args a = app::parse(argc, argv, spec);
    const auto& p = a.positional;
    if (p.size() == 4 && p[0] == "wait")
      return logtools::wait_live(a.lcm_url, wait_spec(a), stdout, a.auth);
    if (p.size() == 2 && p[0] == "summary") {
      std::cout << p[1] << ": "
                << logtools::format_summary(logtools::summarize(logtools::read_any_log(p[1])));
      return 0;
    }
    if (p.size() == 3 && p[0] == "restamp")
      return logtools::restamp_log(logtools::read_any_log(p[1]), wall_time_us(), p[2], std::cout,
                                   std::cerr);
    if (p.size() == 3 && (p[0] == "csv" || p[0] == "fields")) {
      const auto all = logtools::read_any_log(p[1]);
      const auto events = logtools::read_any_log(p[1], p[2]);
      if (events.empty()) {
        std::cerr << "tiller-log: no messages on channel " << p[2] << " in " << p[1] << "\n";
        return 1;
      }
      if (p[0] == "fields") return logtools::print_fields(events, p[2], std::cout, std::cerr);
      return logtools::export_csv(events, p[2], app::split_list(a.get("fields")), all.front().time,
                                  a.get("output"), std::cout, std::cerr);
    }
    std::cerr << "tiller-log: expected: summary LOG | csv LOG CHANNEL | fields LOG CHANNEL | "
                 "restamp LOG OUT (see --help)\n";
    return 2;
  });
}
