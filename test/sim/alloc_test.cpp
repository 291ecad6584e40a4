// The simulator's hot path allocates nothing: a model step, and a SimNode tick with ESC output
// delivered as bytes and every output published, after the first (warm-up) cycle. Counted by
// replacing the global operator new in this test executable.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "alloc_count.hpp"
#include "runtime/channels.hpp"
#include "runtime/event.hpp"
#include "sim/sim_node.hpp"

namespace tiller {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

class CountingBus : public Bus {
 public:
  void publish(std::string_view, const std::uint8_t*, int) override { ++published; }
  long published = 0;
};

TEST(SimAllocation, ModelStepAllocatesNothing) {
  for (const char* name : {"otter", "seed001_rov6"}) {
    const auto v = load_sim_vehicle_file(kSrc + "/config/vehicles/" + name + ".yaml");
    std::vector<sim::ThrusterGeometry> g;
    for (const auto& t : v.vehicle.thrusters) g.push_back({t.position, t.direction});
    sim::VesselModel m(v.dynamics, g);
    m.reset(sim::Vector6::Zero(), sim::Vector6::Zero());
    for (int i = 0; i < m.n_thrusters(); ++i) m.set_thrust_target(i, 12.0);
    sim::Environment env;
    env.current_ned = sim::Vector3(0.1, 0.2, 0);
    const long before = test::allocations();
    for (int k = 0; k < 1000; ++k) m.step(0.01, env);
    EXPECT_EQ(test::allocations() - before, 0) << name;
    EXPECT_GT(m.nu().norm(), 0.0);
  }
}

TEST(SimAllocation, SimNodeTickAndEscDeliveryAllocateNothing) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/seed001_rov6.yaml";
  p.current.model = sim::CurrentParams::Model::kGaussMarkov;
  p.current.speed_m_s = 0.2;
  p.current.mu_per_s = 0.1;
  p.current.speed_std_m_s = 0.05;
  p.current.speed_max_m_s = 0.5;
  p.noise.position_std_m = 0.1;
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  CountingBus bus;
  node.attach(&bus);
  esc_output_t m{};
  m.armed = true;
  m.unit = esc_output_t::UNIT_PULSE_US;
  m.n_channels = node.vehicle().size();
  for (const auto& t : node.vehicle().thrusters) {
    m.names.push_back(t.name);
    m.channel.push_back(0);
    m.value.push_back(1650);
    m.normalized.push_back(0.3);
  }
  Event e = encode(channels::kEscOutput, 0, m);
  const std::string channel = channels::kEscOutput;  // made once: the executors keep theirs
  TimeUs now = 0;
  auto cycle = [&] {
    m.utime = now;  // stamped as tiller-esc does (re-encoded in place: the size is the same)
    m.encode(e.data.data(), 0, static_cast<int>(e.data.size()));
    node.deliver(channel, e.data.data(), static_cast<int>(e.data.size()), now);
    node.tick(now);
    now += p.step_us;
  };
  for (int k = 0; k < 200; ++k) cycle();  // warm-up: buffers reach their size, heartbeat sent
  const long before = test::allocations();
  const long published_before = bus.published;
  for (int k = 0; k < 2000; ++k) cycle();  // 20 s: 400 odometry, ground truth and states each
  EXPECT_EQ(test::allocations() - before, 0);
  EXPECT_GE(bus.published - published_before, 1200);
  EXPECT_EQ(node.rejected(), 0);
}

// With every simulated sensor on (the USV's file with GNSS as both TILLER_GNSS and NMEA to a
// sink, then the ROV's with depth): sampling, noise, delay lines, NMEA text and publishing.
TEST(SimAllocation, SimulatedSensorsAllocateNothing) {
  struct Sink : sim::NmeaSink {
    long bytes = 0;
    void write(const char*, std::size_t n) override { bytes += static_cast<long>(n); }
  };
  for (const char* which : {"usv", "rov"}) {
    SimParams p;
    p.vehicle_file = kSrc + (std::string(which) == "usv" ? "/config/vehicles/otter.yaml"
                                                         : "/config/vehicles/seed001_rov6.yaml");
    p.sensors = sim::load_sensor_file(kSrc + "/config/sim/sensors/" + which + ".yaml", p.step_us);
    p.sensors.gnss_nmea = true;
    p.sensors.imu_timing.latency_us = 20'000;
    p.sensors.imu_timing.dropout_probability = 0.1;
    p.sensors.gnss_outages.push_back({from_seconds(5), from_seconds(8)});
    p.sensors.leak.wet_after_s = 10;
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    Sink sink;
    node.set_nmea_sink(&sink);
    CountingBus bus;
    node.attach(&bus);
    TimeUs now = 0;
    for (int k = 0; k < 300; ++k, now += p.step_us) node.tick(now);  // warm-up: 3 s
    const long before = test::allocations();
    const long published_before = bus.published;
    for (int k = 0; k < 2000; ++k, now += p.step_us) node.tick(now);  // 20 s, outage, leak
    EXPECT_EQ(test::allocations() - before, 0) << which;
    EXPECT_GE(bus.published - published_before, 2000) << which;  // IMU alone: 1800
    if (std::string(which) == "usv") {
      EXPECT_GT(sink.bytes, 100 * 200) << which;
    }
  }
}

}  // namespace
}  // namespace tiller
