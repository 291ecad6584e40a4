// tiller-log: looks inside an LCM log.
//   tiller-log summary LOG                      channels, types, counts, rates, gaps; per process
//                                               its last heartbeat and non-zero drop counters
//   tiller-log csv LOG CHANNEL [--fields F,..] [--output FILE]
//                                               one CSV row per message, fields decoded by name
//   tiller-log fields LOG CHANNEL               the field paths of a channel's first message
#include <fstream>
#include <iostream>
#include <sstream>

#include "logtools/csv.hpp"
#include "logtools/lcm_schema.hpp"
#include "logtools/logsummary.hpp"
#include "runtime/app.hpp"
#include "runtime/log.hpp"

using namespace tiller;

namespace {
std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-log", [&] {
    const app::Spec spec{
        "tiller-log",
        "Summarises an LCM log or exports channels to CSV.\n"
        "Usage: tiller-log summary LOG | csv LOG CHANNEL [--fields F,..] [--output FILE] | fields "
        "LOG CHANNEL",
        "",
        {{"fields", "F[,F..]", "fields to export (path or prefix: position, command, waypoints[0])",
          ""},
         {"output", "FILE", "write the CSV here instead of standard output", ""}}};
    const app::Args a = app::parse(argc, argv, spec);
    const auto& p = a.positional;
    if (p.size() == 2 && p[0] == "summary") {
      std::cout << p[1] << ": " << logtools::format_summary(logtools::summarize(read_log(p[1])));
      return 0;
    }
    if (p.size() == 3 && (p[0] == "csv" || p[0] == "fields")) {
      const auto all = read_log(p[1]);
      const auto events = read_log(p[1], p[2]);
      if (events.empty()) {
        std::cerr << "tiller-log: no messages on channel " << p[2] << " in " << p[1] << "\n";
        return 1;
      }
      if (p[0] == "fields") {
        logtools::Decoded d;
        if (!logtools::tiller_types().decode(events[0].data.data(), events[0].data.size(), d)) {
          std::cerr << "tiller-log: " << p[2] << " does not carry a Tiller type\n";
          return 1;
        }
        std::cout << p[2] << ": " << d.type->name << "\n";
        for (const auto& f : d.fields)
          std::cout << "  " << f.path << " = " << f.to_string() << "\n";
        return 0;
      }
      std::size_t skipped = 0;
      std::size_t rows = 0;
      const TimeUs t0 = all.front().time;
      if (a.get("output").empty()) {
        rows =
            logtools::write_csv(std::cout, events, p[2], split_list(a.get("fields")), t0, &skipped);
      } else {
        std::ofstream out(a.get("output"));
        if (!out) throw std::runtime_error("cannot write " + a.get("output"));
        rows = logtools::write_csv(out, events, p[2], split_list(a.get("fields")), t0, &skipped);
        std::cerr << "tiller-log: " << rows << " rows to " << a.get("output") << "\n";
      }
      if (skipped)
        std::cerr << "tiller-log: " << skipped << " messages did not decode and were skipped\n";
      return rows > 0 ? 0 : 1;
    }
    std::cerr << "tiller-log: expected: summary LOG | csv LOG CHANNEL | fields LOG CHANNEL (see "
                 "--help)\n";
    return 2;
  });
}
