#include "plants.hpp"

#include "core/angles.hpp"
#include "esc/esc_node.hpp"
#include "harness.hpp"
#include "mixer/mixer_node.hpp"
#include "sim/sim_node.hpp"
#include "simple_plant.hpp"

namespace tiller::test {

namespace {

// Simulator + ESC (sim backend) + mixer for a vehicle, from the shipped config files, with the
// mission's start pose and a constant current coming FROM `from` (flowing toward from + pi).
std::vector<std::unique_ptr<Node>> full_stack(const std::string& vehicle, const mission::Mission& m,
                                              double speed, double from) {
  const auto sroot = config::Value::load_file(source_path("config/sim/sim.yaml"));
  SimParams sp = load_sim_params(sroot);
  sp.vehicle_file = source_path("config/vehicles/" + vehicle + ".yaml");
  const auto s = m.start.value_or(mission::MissionPoint{});
  sp.initial_eta.setZero();
  sp.initial_eta[0] = s.north;
  sp.initial_eta[1] = s.east;
  sp.initial_eta[5] = s.heading;
  sp.current.model =
      speed > 0 ? sim::CurrentParams::Model::kConstant : sim::CurrentParams::Model::kNone;
  sp.current.speed_m_s = speed;
  sp.current.toward_rad = wrap_pi(from + kPi);
  std::vector<std::unique_ptr<Node>> n;
  n.push_back(std::make_unique<SimNode>(sp, load_sim_vehicle_file(sp.vehicle_file)));
  n.push_back(std::make_unique<EscNode>(source_path("config/esc/" + vehicle + "_sim.yaml")));
  n.push_back(std::make_unique<MixerNode>(source_path("config/mixer/" + vehicle + ".yaml")));
  return n;
}

}  // namespace

PlantSpec full_plant(const std::string& vehicle) {
  return {vehicle, "config/control/" + vehicle + ".yaml", "config/guidance/" + vehicle + ".yaml",
          "TILLER_GROUND_TRUTH", [vehicle](const mission::Mission& m, double speed, double from) {
            return full_stack(vehicle, m, speed, from);
          }};
}

const std::vector<PlantSpec>& plants() {
  static const std::vector<PlantSpec> p = [] {
    std::vector<PlantSpec> v;
    v.push_back(full_plant("otter"));
    v.push_back(full_plant("seed004_usv_x"));
    v.push_back(full_plant("seed004_usv_h"));
    return v;
  }();
  return p;
}

const PlantSpec& standin_plant() {
  static const PlantSpec p{
      "otter-standin", "config/control/otter.yaml", "config/guidance/otter.yaml", "TILLER_ODOMETRY",
      [](const mission::Mission& m, double speed, double from) {
        std::vector<std::unique_ptr<Node>> n;
        const auto s = m.start.value_or(mission::MissionPoint{});
        n.push_back(std::make_unique<SimplePlant>(speed, from, s.north, s.east, s.heading));
        return n;
      }};
  return p;
}

}  // namespace tiller::test
