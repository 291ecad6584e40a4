#include "runtool/sweep.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "scores/path_metrics.hpp"

namespace tiller::runtool {

namespace {

constexpr const char* kFileKinds[] = {"vehicle", "sim", "esc", "mixer", "control", "guidance"};
constexpr const char* kSimOptions[] = {
    "current-speed", "current-toward-deg", "seed",       "north",
    "east",          "heading-deg",        "mass-scale", "damping-scale"};

bool is_number(const std::string& s, double* out = nullptr) {
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return false;
  if (out) *out = v;
  return true;
}

template <std::size_t N>
bool one_of(const std::string& s, const char* const (&list)[N]) {
  for (const char* x : list)
    if (s == x) return true;
  return false;
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// What the table and the plot show for a value: a file's name without its folder.
std::string label(const Axis& a, const std::string& v) {
  if (one_of(a.name, kFileKinds)) return std::filesystem::path(v).filename().string();
  return v;
}

// The scores as the child process reports them to the parent: one line of text.
std::string encode_row(const Row& r) {
  std::ostringstream os;
  os.precision(17);
  os << "ok " << r.completed << " " << r.xte_rms << " " << r.xte_max << " " << r.time_s << " "
     << r.final_m << " " << r.heading_rad << " " << r.vrx_way << " " << r.vrx_sk << " " << r.sim_s
     << " " << r.missed << " " << r.steady_rms << " " << r.overshoot << " " << r.max_setpoint << " "
     << r.max_speed << " " << r.path_m << " " << r.final_30 << " " << r.est_rms << " "
     << r.est_head_deg << " " << r.est_xte_rms << " " << r.est_steady_rms << " " << r.est_missed
     << " " << r.weaving << "\n";
  return os.str();
}

Row decode_row(const std::string& text) {
  Row r;
  std::istringstream is(text);
  std::string tag;
  is >> tag;
  if (tag == "ok") {
    is >> r.completed >> r.xte_rms >> r.xte_max >> r.time_s >> r.final_m >> r.heading_rad >>
        r.vrx_way >> r.vrx_sk >> r.sim_s >> r.missed >> r.steady_rms >> r.overshoot >>
        r.max_setpoint >> r.max_speed >> r.path_m >> r.final_30 >> r.est_rms >> r.est_head_deg >>
        r.est_xte_rms >> r.est_steady_rms >> r.est_missed >> r.weaving;
    r.ok = !is.fail();
    if (!r.ok) r.error = "unreadable result '" + text + "'";
  } else if (tag == "error") {
    std::getline(is >> std::ws, r.error);
  } else {
    r.error = text.empty() ? "the run's process gave no result" : text;
  }
  return r;
}

void write_all(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

std::string read_all(int fd) {
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

}  // namespace

std::vector<std::string> split_top_level(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  char quote = 0;
  for (char c : s) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == ',' && depth == 0) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
      continue;
    }
    cur += c;
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string expand_file(const std::string& kind, const std::string& value) {
  const auto ends = [&](const char* e) {
    const std::string x(e);
    return value.size() >= x.size() && value.compare(value.size() - x.size(), x.size(), x) == 0;
  };
  if (value.find('/') != std::string::npos || ends(".yaml") || ends(".yml") || ends(".csv"))
    return value;
  const std::string dir = kind == "vehicle" ? "vehicles" : kind;
  return "config/" + dir + "/" + value + ".yaml";
}

Axis parse_axis(const std::string& text) {
  const auto eq = text.find('=');
  const std::string usage =
      " (expected NAME=FROM:TO:COUNT or NAME=V1,V2,..., NAME a setting FILE.KEY, one of vehicle, "
      "sim, esc, mixer, control, guidance, or a simulator option: current-speed, "
      "current-toward-deg, seed, north, east, heading-deg, mass-scale, damping-scale)";
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw std::runtime_error("'" + text + "'" + usage);
  Axis a;
  a.name = text.substr(0, eq);
  const std::string rest = text.substr(eq + 1);
  if (a.name.find('.') != std::string::npos) {
    parse_setting(a.name + "=x");  // checks FILE
  } else if (!one_of(a.name, kFileKinds) && !one_of(a.name, kSimOptions)) {
    throw std::runtime_error("'" + text + "': unknown name '" + a.name + "'" + usage);
  }
  // FROM:TO:COUNT
  const auto c1 = rest.find(':');
  const auto c2 = c1 == std::string::npos ? c1 : rest.find(':', c1 + 1);
  double from = 0, to = 0, count = 0;
  if (c2 != std::string::npos && is_number(rest.substr(0, c1), &from) &&
      is_number(rest.substr(c1 + 1, c2 - c1 - 1), &to) && is_number(rest.substr(c2 + 1), &count)) {
    if (count < 1 || count > 1000 || count != std::floor(count))
      throw std::runtime_error("'" + text +
                               "': COUNT: expected a whole number in [1, 1000], got '" +
                               rest.substr(c2 + 1) + "'");
    const int n = static_cast<int>(count);
    for (int i = 0; i < n; ++i)
      a.values.push_back(fmt(n == 1 ? from : from + (to - from) * i / (n - 1)));
  } else {
    a.values = split_top_level(rest);
  }
  if (a.values.empty()) throw std::runtime_error("'" + text + "': no values" + usage);
  if (one_of(a.name, kFileKinds)) {
    for (auto& v : a.values) v = expand_file(a.name, v);
  }
  a.numeric = true;
  for (const auto& v : a.values) a.numeric = a.numeric && is_number(v);
  return a;
}

RunSpec spec_at(const RunSpec& base, const std::vector<Axis>& axes,
                const std::vector<std::size_t>& index) {
  RunSpec s = base;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const Axis& a = axes[k];
    const std::string& v = a.values.at(index.at(k));
    if (a.name == "vehicle")
      s.vehicle_file = v;
    else if (a.name == "sim")
      s.sim_file = v;
    else if (a.name == "esc")
      s.esc_file = v;
    else if (a.name == "mixer")
      s.mixer_file = v;
    else if (a.name == "control")
      s.control_file = v;
    else if (a.name == "guidance")
      s.guidance_file = v;
    else if (one_of(a.name, kSimOptions))
      s.sim_args.insert(s.sim_args.end(), {"--" + a.name, v});
    else
      s.settings.push_back(parse_setting(a.name + "=" + v));
  }
  return s;
}

Row row_of(const RunOutcome& o) {
  Row r;
  const auto& p = o.scores.path_scores;
  r.ok = true;
  r.completed = o.completed;
  r.xte_rms = p.cross_track_rms;
  r.xte_max = p.cross_track_max;
  r.time_s = p.time_to_complete;
  r.final_m = p.final_position_error;
  r.heading_rad = p.final_heading_error;
  r.vrx_way = p.vrx_wayfinding;
  r.vrx_sk = o.scores.station_keeping;
  r.sim_s = o.sim_s;
  r.missed = p.waypoints_missed;
  const auto& c = o.scores.corners;  // the one definition, as tiller-score prints it
  r.steady_rms = c.steady_cross_track_rms;
  r.weaving = c.weaving;
  if (o.estimated) {
    r.est_rms = o.scores.position_error_rms;
    r.est_head_deg = o.scores.heading_error_rms * 180.0 / M_PI;
    if (o.scores.estimate_path_scores) {
      r.est_xte_rms = o.scores.estimate_path_scores->cross_track_rms;
      r.est_missed = o.scores.estimate_path_scores->waypoints_missed;
      if (o.scores.estimate_corners)
        r.est_steady_rms = o.scores.estimate_corners->steady_cross_track_rms;
    }
  }
  r.overshoot = c.max_overshoot;
  r.max_setpoint = o.max_setpoint_speed;
  r.max_speed = o.max_speed;
  for (std::size_t k = 1; k < o.scores.path.size(); ++k) {
    r.path_m += std::hypot(o.scores.path[k].north - o.scores.path[k - 1].north,
                           o.scores.path[k].east - o.scores.path[k - 1].east);
  }
  if (o.completed && !o.scores.path.empty() && !o.scores.poses.empty()) {
    const auto& g = o.scores.path.back();
    const scores::Pose* at = &o.scores.poses.back();
    for (const auto& q : o.scores.poses) {
      if (q.t >= o.completed_at + 30) {
        at = &q;
        break;
      }
    }
    r.final_30 = std::hypot(at->north - g.north, at->east - g.east);
  }
  return r;
}

std::vector<Row> sweep(const RunSpec& base, const std::vector<Axis>& axes, int jobs,
                       const std::string& log_dir) {
  std::vector<std::vector<std::size_t>> points(1);
  for (const auto& a : axes) {
    std::vector<std::vector<std::size_t>> next;
    for (const auto& p : points) {
      for (std::size_t i = 0; i < a.values.size(); ++i) {
        next.push_back(p);
        next.back().push_back(i);
      }
    }
    points = std::move(next);
  }
  std::vector<Row> rows(points.size());
  if (!log_dir.empty()) std::filesystem::create_directories(log_dir);
  struct Child {
    pid_t pid;
    int fd;
    std::size_t i;
  };
  std::vector<Child> active;
  std::size_t next = 0;
  std::fflush(stdout);
  std::fflush(stderr);
  const auto start = [&](std::size_t i) {
    int fds[2];
    if (::pipe(fds) != 0) throw std::runtime_error("sweep: pipe() failed");
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("sweep: fork() failed");
    if (pid == 0) {
      ::close(fds[0]);
      std::string line;
      try {
        RunSpec s = spec_at(base, axes, points[i]);
        if (!log_dir.empty()) s.log_file = log_dir + "/run-" + std::to_string(i) + ".lcmlog";
        line = encode_row(row_of(run(s)));
      } catch (const std::exception& e) {
        std::string m = e.what();
        for (char& c : m)
          if (c == '\n') c = ' ';
        line = "error " + m + "\n";
      }
      write_all(fds[1], line);
      ::_exit(0);
    }
    ::close(fds[1]);
    active.push_back({pid, fds[0], i});
  };
  while (next < points.size() || !active.empty()) {
    while (static_cast<int>(active.size()) < std::max(jobs, 1) && next < points.size())
      start(next++);
    int st = 0;
    const pid_t pid = ::waitpid(-1, &st, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("sweep: waitpid() failed");
    }
    for (auto it = active.begin(); it != active.end(); ++it) {
      if (it->pid != pid) continue;
      Row r = decode_row(read_all(it->fd));
      ::close(it->fd);
      if (!WIFEXITED(st) || WEXITSTATUS(st) != 0)
        r = Row{{},
                false,
                WIFSIGNALED(st) ? "the run's process died of signal " + std::to_string(WTERMSIG(st))
                                : "the run's process exited " + std::to_string(WEXITSTATUS(st))};
      r.index = points[it->i];
      rows[it->i] = r;
      active.erase(it);
      break;
    }
  }
  return rows;
}

namespace {
struct Metric {
  const char* name;
  const char* title;
  double Row::*field;
};
constexpr Metric kMetrics[] = {
    {"xte_rms", "cross-track RMS [m]", &Row::xte_rms},
    {"xte_max", "cross-track max [m]", &Row::xte_max},
    {"time_s", "time to complete [s]", &Row::time_s},
    {"final_m", "final position error [m]", &Row::final_m},
    {"vrx_way", "VRX wayfinding", &Row::vrx_way},
    {"vrx_sk", "VRX station keeping", &Row::vrx_sk},
    {"steady_rms", "steady cross-track RMS (60 s after each passage, 10 m before each corner) [m]",
     &Row::steady_rms},
    {"overshoot", "largest corner overshoot [m]", &Row::overshoot},
    {"weaving", "weaving: RMS heading rate on the steady stretches [rad/s]", &Row::weaving},
    {"max_sp", "largest speed setpoint [m/s]", &Row::max_setpoint},
};

// A score shown for a row, or NaN when it has none (failed, or not completed for the time).
double value_of(const Row& r, const Metric& m) {
  if (!r.ok) return NAN;
  const double v = r.*m.field;
  if ((m.field == &Row::time_s || m.field == &Row::vrx_sk || m.field == &Row::steady_rms ||
       m.field == &Row::weaving) &&
      v < 0)
    return NAN;
  return v;
}
}  // namespace

void print_table(const std::vector<Axis>& axes, const std::vector<Row>& rows, std::FILE* out) {
  std::vector<int> width;
  for (const auto& a : axes) {
    std::size_t w = a.name.size();
    for (const auto& v : a.values) w = std::max(w, label(a, v).size());
    width.push_back(static_cast<int>(w));
  }
  for (std::size_t k = 0; k < axes.size(); ++k)
    std::fprintf(out, "%-*s  ", width[k], axes[k].name.c_str());
  // On estimated state: the estimation RMS, and the cross-track RMS and waypoints missed on the
  // estimate (the pose the follower followed).
  bool estimated = false;
  for (const auto& r : rows) estimated |= r.ok && r.est_rms >= 0;
  std::fprintf(out, "%8s %8s %7s %8s %8s %8s %10s %9s %8s %7s %6s %5s", "xte_rms", "xte_max",
               "time_s", "final_m", "vrx_way", "vrx_sk", "steady_rms", "overshoot", "weaving",
               "max_sp", "missed", "done");
  if (estimated) std::fprintf(out, " %7s %11s %10s", "est_rms", "est_xte_rms", "est_missed");
  std::fprintf(out, "\n");
  for (const auto& r : rows) {
    for (std::size_t k = 0; k < axes.size(); ++k)
      std::fprintf(out, "%-*s  ", width[k], label(axes[k], axes[k].values[r.index[k]]).c_str());
    if (!r.ok) {
      std::fprintf(out, "error: %s\n", r.error.c_str());
      continue;
    }
    char steady[16] = "         -";  // no leg long enough
    if (r.steady_rms >= 0) std::snprintf(steady, sizeof steady, "%10.4f", r.steady_rms);
    char weave[16] = "       -";
    if (r.weaving >= 0) std::snprintf(weave, sizeof weave, "%8.4f", r.weaving);
    std::fprintf(out, "%8.3f %8.3f %7.1f %8.3f %8.3f %8.3f %s %9.3f %s %6.3f%s %6d %5s", r.xte_rms,
                 r.xte_max, r.time_s, r.final_m, r.vrx_way, r.vrx_sk, steady, r.overshoot, weave,
                 r.max_setpoint, r.max_setpoint > r.max_speed + 1e-9 ? "!" : " ", r.missed,
                 r.completed ? "yes" : "no");
    if (estimated) std::fprintf(out, " %7.3f %11.3f %10d", r.est_rms, r.est_xte_rms, r.est_missed);
    std::fprintf(out, "\n");
  }
  // The best run for each score (lower is better for every one).
  for (const auto& m : kMetrics) {
    const Row* best = nullptr;
    for (const auto& r : rows) {
      const double v = value_of(r, m);
      if (!std::isnan(v) && (!best || v < value_of(*best, m))) best = &r;
    }
    if (!best) continue;
    std::fprintf(out, "lowest %-8s %8.3f at", m.name, value_of(*best, m));
    for (std::size_t k = 0; k < axes.size(); ++k)
      std::fprintf(out, " %s=%s", axes[k].name.c_str(),
                   label(axes[k], axes[k].values[best->index[k]]).c_str());
    std::fprintf(out, "\n");
  }
}

std::string csv(const std::vector<Axis>& axes, const std::vector<Row>& rows) {
  std::ostringstream os;
  os.precision(10);
  for (std::size_t k = 0; k < axes.size(); ++k) os << "i" << k << ",";
  for (const auto& a : axes) os << a.name << ",";
  os << "completed";
  for (const auto& m : kMetrics) os << "," << m.name;
  os << ",missed,max_speed,path_m,sim_s,final_30,est_rms,est_head_deg,est_xte_rms,est_steady_rms,"
        "est_missed,error\n";
  for (const auto& r : rows) {
    for (std::size_t k = 0; k < axes.size(); ++k) os << r.index[k] << ",";
    for (std::size_t k = 0; k < axes.size(); ++k)
      os << label(axes[k], axes[k].values[r.index[k]]) << ",";
    os << (r.ok && r.completed ? 1 : 0);
    for (const auto& m : kMetrics) {
      const double v = value_of(r, m);
      os << ",";
      if (std::isnan(v))
        os << "NaN";
      else
        os << v;
    }
    os << "," << (r.ok ? std::to_string(r.missed) : "NaN") << ",";
    if (r.ok)
      os << r.max_speed << "," << r.path_m << "," << r.sim_s << ","
         << (r.final_30 >= 0 ? std::to_string(r.final_30) : "NaN") << ","
         << (r.est_rms >= 0 ? std::to_string(r.est_rms) : "NaN") << ","
         << (r.est_head_deg >= 0 ? std::to_string(r.est_head_deg) : "NaN") << ","
         << (r.est_xte_rms >= 0 ? std::to_string(r.est_xte_rms) : "NaN") << ","
         << (r.est_steady_rms >= 0 ? std::to_string(r.est_steady_rms) : "NaN") << ","
         << (r.est_rms >= 0 ? std::to_string(r.est_missed) : "NaN");
    else
      os << "NaN,NaN,NaN,NaN,NaN,NaN,NaN,NaN,NaN";
    os << ",";
    std::string e = r.error;
    for (char& c : e)
      if (c == ',' || c == '"') c = ';';
    os << e << "\n";
  }
  return os.str();
}

std::string gnuplot_script(const std::vector<Axis>& axes, const std::vector<Row>& rows,
                           const std::string& data_file, const std::string& png,
                           const std::string& title) {
  const std::size_t n = axes.size();
  // A score no run has (e.g. steady cross-track on legs shorter than 60 s) is not drawn: gnuplot
  // refuses a plot with no valid point.
  const auto drawn = [&](const Metric& m) {
    for (const auto& r : rows)
      if (!std::isnan(value_of(r, m))) return true;
    return false;
  };
  std::string t = title;
  for (char& ch : t)
    if (ch == '\'') ch = '"';
  // Columns: i0[,i1], values, completed, the metrics.
  const auto metric_col = [&](std::size_t j) { return 2 * n + 2 + j; };
  const auto tics = [&](const Axis& a) {
    std::string list = "(";
    for (std::size_t i = 0; i < a.values.size(); ++i) {
      list += (i ? ", \"" : "\"") + label(a, a.values[i]) + "\" " + std::to_string(i);
    }
    return list + ")";
  };
  std::ostringstream g;
  g << "set terminal pngcairo size 1500,1200 font 'sans,10' noenhanced\n"
    << "set output '" << png << "'\n"
    << "set datafile separator ','\nset datafile missing 'NaN'\nset grid\nset key off\n"
    << "set multiplot layout 3,3 title '" << t << "'\n";
  if (n == 1) {
    const Axis& a = axes[0];
    g << "set xlabel '" << a.name << "'\n";
    // Files or words: points at their index, no line between them (they are not in an order).
    if (!a.numeric)
      g << "set xtics " << tics(a) << " rotate by -20\nset xrange [-0.5:" << a.values.size() - 0.5
        << "]\n";
    const std::string x = a.numeric ? "2" : "1";
    const std::string style = a.numeric ? "linespoints pt 7 lw 2" : "points pt 7 ps 2";
    for (std::size_t j = 0; j < std::size(kMetrics); ++j) {
      if (!drawn(kMetrics[j])) continue;
      g << "set title '" << kMetrics[j].title << "'\n"
        << "plot '" << data_file << "' skip 1 using " << x << ":" << metric_col(j) << " with "
        << style << "\n";
    }
  } else {
    g << "set xlabel '" << axes[0].name << "'\nset ylabel '" << axes[1].name << "'\n"
      << "set xtics " << tics(axes[0]) << "\nset ytics " << tics(axes[1]) << "\n"
      << "set xrange [-0.5:" << axes[0].values.size() - 0.5
      << "]\nset yrange [-0.5:" << axes[1].values.size() - 0.5 << "]\n"
      << "set palette defined (0 '#1a9850', 0.5 '#fee08b', 1 '#d73027')\n";
    for (std::size_t j = 0; j < std::size(kMetrics); ++j) {
      if (!drawn(kMetrics[j])) continue;
      const std::size_t c = metric_col(j);
      g << "set title '" << kMetrics[j].title << " (lower is better)'\n"
        << "plot '" << data_file << "' skip 1 using 1:2:(0.5):(0.5):" << c
        << " with boxxyerror fs solid 1 lc palette, '' skip 1 using 1:2:(sprintf('%.3g', $" << c
        << ")) with labels font 'sans,9'\n";
    }
  }
  g << "unset multiplot\n";
  return g.str();
}

bool run_gnuplot(const std::string& script) {
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) {
    ::execlp("gnuplot", "gnuplot", script.c_str(), static_cast<char*>(nullptr));
    std::fprintf(stderr, "tiller-run: cannot run gnuplot (tools/setup installs gnuplot-nox)\n");
    ::_exit(127);
  }
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

}  // namespace tiller::runtool
