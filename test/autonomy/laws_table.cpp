// Development tool (not a test): the cross-track laws on a mission for the Otter (full plant:
// simulator, ESC, mixer), in still water and in a current from 8 directions, as the table in
// docs/tuning.md. Usage: autonomy_laws_table [MISSION] [TURN_RATE] [LOOKAHEAD] [KAPPA] [GAMMA]
//                                            [MAX_SPEED] [CURRENT] [LAWS...]
// (a value "-" keeps the shipped config/guidance/otter.yaml setting).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "harness.hpp"
#include "plants.hpp"

using namespace tiller;

int main(int argc, char** argv) {
  const auto arg = [&](int k) -> const char* {
    return argc > k && std::string(argv[k]) != "-" ? argv[k] : nullptr;
  };
  const std::string mission = arg(1) ? arg(1) : "config/missions/long_course.yaml";
  const char* laws_default[] = {"seed", "los", "integral", "adaptive"};
  std::vector<std::string> laws;
  for (int k = 8; k < argc; ++k) laws.push_back(argv[k]);
  if (laws.empty()) laws.assign(std::begin(laws_default), std::end(laws_default));
  const double current = arg(7) ? std::atof(arg(7)) : 0.3;
  const auto& otter = test::plants()[0];
  std::printf("%-9s %8s %9s %9s %9s %8s %7s %7s %6s\n", "law", "toward", "steadyRMS", "xte_rms",
              "overshoot", "max_sp", "time", "t/(L/U)", "miss");
  for (const auto& law : laws) {
    const int dirs = std::getenv("STILL") ? 0 : 8;
    for (int dir = -1; dir < dirs; ++dir) {
      test::RunConfig c;
      c.mission_file = mission;
      c.guidance_file = otter.guidance_file;
      c.control_file = otter.control_file;
      c.make_plant = otter.make;
      c.pose_channel = otter.pose_channel;
      c.current_speed = dir < 0 ? 0.0 : current;
      const double toward = dir < 0 ? 0 : 45.0 * dir;
      c.current_from_deg = toward + 180;
      c.tweak_follower = [&](guidance::FollowerNodeParams& p) {
        auto& f = p.follower;
        f.law = law == "seed"       ? guidance::CrossTrackLaw::kSeed
                : law == "los"      ? guidance::CrossTrackLaw::kLos
                : law == "integral" ? guidance::CrossTrackLaw::kIntegral
                                    : guidance::CrossTrackLaw::kAdaptive;
        if (arg(2)) f.turn_rate = std::atof(arg(2));
        if (arg(3)) f.lookahead = std::atof(arg(3));
        if (arg(4)) f.integral_kappa = std::atof(arg(4));
        if (arg(5)) f.adaptive_gamma = std::atof(arg(5));
        if (arg(6)) f.max_speed = std::atof(arg(6));
        if (std::getenv("ZONE")) f.integral_zone = std::atof(std::getenv("ZONE"));
      };
      const auto r = test::run_mission(c);
      double len = 0;
      for (std::size_t k = 1; k < r.mission.waypoints.size(); ++k) {
        len += std::hypot(r.mission.waypoints[k].north - r.mission.waypoints[k - 1].north,
                          r.mission.waypoints[k].east - r.mission.waypoints[k - 1].east);
      }
      if (std::getenv("POSES")) {
        for (const auto& p : r.poses)
          if (p.t > 160 && p.t < 280 && static_cast<int>(p.t * 10) % 10 == 0)
            std::printf("%.0f %.2f %.2f %.2f\n", p.t, p.north, p.east, p.heading);
      }
      if (std::getenv("DEBUG")) {
        for (double p : r.corners.passage) std::printf(" %.1f", p);
        for (double o : r.corners.overshoot) std::printf(" o%.2f", o);
        std::printf("\n");
      }
      const double cruise = arg(6) ? std::atof(arg(6)) : 1.5;
      std::printf("%-9s %8s %9.4f %9.3f %9.3f %8.3f %7.1f %7.3f %6d\n", law.c_str(),
                  dir < 0 ? "still" : std::to_string(static_cast<int>(toward)).c_str(),
                  r.corners.steady_cross_track_rms, r.path.cross_track_rms, r.corners.max_overshoot,
                  r.max_setpoint_speed, r.completed ? r.completed_at : -1.0,
                  r.completed ? r.completed_at / (len / cruise) : -1.0, r.path.waypoints_missed);
      std::fflush(stdout);
    }
  }
}
