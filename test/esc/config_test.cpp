// tiller-esc config: every preset in config/esc loads and covers its vehicle; mistakes are
// refused with the file, the key and what was expected.
#include <gtest/gtest.h>

#include <filesystem>

#include "esc/esc_config.hpp"
#include "esc_rig.hpp"
#include "i2c/linux_i2c.hpp"

namespace tiller::test {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_config(yaml);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "";
}

TEST(EscConfig, EveryPresetLoadsAndCoversItsVehicle) {
  int n = 0;
  for (const auto& f :
       std::filesystem::directory_iterator(std::string(TILLER_SOURCE_DIR) + "/config/esc")) {
    if (f.path().extension() != ".yaml") continue;
    SCOPED_TRACE(f.path().string());
    const esc::EscConfig c = esc::load_esc_config_file(f.path().string());
    EXPECT_FALSE(c.escs.empty());
    EXPECT_TRUE(std::filesystem::exists(c.vehicle_file));
    // The backend builds (hardware presets over a fake bus).
    i2c::FakeBus bus;
    auto b = esc::make_backend(c, &bus);
    EXPECT_EQ(b->size(), c.escs.size());
    ++n;
  }
  EXPECT_GE(n, 11);
}

TEST(EscConfig, SeedPresets) {
  const auto c0 =
      esc::load_esc_config_file(std::string(TILLER_SOURCE_DIR) + "/config/esc/seed000_i2c.yaml");
  EXPECT_EQ(c0.backend, "i2c_tgy");
  ASSERT_EQ(c0.escs.size(), 4u);
  EXPECT_EQ(c0.escs[0].name, "t1");
  EXPECT_EQ(c0.escs[0].address, 0x29);
  EXPECT_EQ(c0.escs[3].address, 0x2c);
  EXPECT_EQ(c0.tgy.bus, "/dev/i2c-1");
  EXPECT_EQ(c0.node.command_timeout_us, 250'000);
  const auto c1 = esc::load_esc_config_file(std::string(TILLER_SOURCE_DIR) +
                                            "/config/esc/seed001_pca9685.yaml");
  EXPECT_EQ(c1.backend, "pca9685");
  EXPECT_EQ(c1.pca9685.address, 0x40);
  EXPECT_EQ(esc::pca9685::prescale(c1.pca9685), 121);
}

TEST(EscConfig, ReversedComesFromTheVehicleFile) {
  const auto c = parse_config(sim_yaml());
  ASSERT_EQ(c.escs.size(), 4u);
  EXPECT_FALSE(c.escs[0].reversed);
  EXPECT_TRUE(c.escs[2].reversed);  // back_left in rov4.yaml
  const std::string e = error_of(sim_yaml("", ", reversed: true"));
  EXPECT_NE(e.find("escs[0].reversed"), std::string::npos) << e;
  EXPECT_NE(e.find("vehicle file"), std::string::npos) << e;
}

TEST(EscConfig, MistakesAreRefusedWithTheKey) {
  // An ESC for a thruster the vehicle does not have.
  std::string e = error_of(
      "vehicle: rov4.yaml\nbackend: sim\nescs:\n  - {name: front_right}\n  - {name: front_left}\n"
      "  - {name: back_left}\n  - {name: back_rigth}\n");
  EXPECT_NE(e.find("inline.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("escs[3].name"), std::string::npos) << e;
  EXPECT_NE(e.find("back_rigth"), std::string::npos) << e;
  // A thruster without an ESC.
  e = error_of(
      "vehicle: rov4.yaml\nbackend: sim\nescs:\n  - {name: front_right}\n  - {name: front_left}\n"
      "  - {name: back_left}\n");
  EXPECT_NE(e.find("thruster back_right has none"), std::string::npos) << e;
  // Two ESCs on one address.
  e = error_of(tgy_yaml().replace(tgy_yaml().find("0x2a"), 4, "0x29"));
  EXPECT_NE(e.find("escs[1].address"), std::string::npos) << e;
  // Unknown key (a typo).
  e = error_of(sim_yaml("comand_timeout_ms: 100\n"));
  EXPECT_NE(e.find("comand_timeout_ms"), std::string::npos) << e;
  // Out of range.
  e = error_of(sim_yaml("command_timeout_ms: 0\n"));
  EXPECT_NE(e.find("command_timeout_ms"), std::string::npos) << e;
  e = error_of(sim_yaml("", ", trim: 1.5"));
  EXPECT_NE(e.find("escs[0].trim"), std::string::npos) << e;
  // Unknown backend, missing vehicle file.
  e = error_of("vehicle: rov4.yaml\nbackend: can\nescs: []\n");
  EXPECT_NE(e.find("backend"), std::string::npos) << e;
  e = error_of("vehicle: nowhere.yaml\nbackend: sim\nescs: []\n");
  EXPECT_NE(e.find("nowhere.yaml"), std::string::npos) << e;
  // Pulse widths out of order, PWM frequency the prescaler cannot make.
  const std::string pca =
      "vehicle: rov4.yaml\nbackend: pca9685\npca9685: {address: 0x40, pwm_hz: 50%s}\nescs:\n"
      "  - {name: front_right, channel: 0}\n  - {name: front_left, channel: 1}\n"
      "  - {name: back_left, channel: 2}\n  - {name: back_right, channel: 16}\n";
  e = error_of(std::string(pca).replace(pca.find("%s"), 2, ""));
  EXPECT_NE(e.find("escs[3].channel"), std::string::npos) << e;
  e = error_of(std::string(pca).replace(pca.find("%s"), 2, ", min_us: 1600"));
  EXPECT_NE(e.find("min_us < neutral_us < max_us"), std::string::npos) << e;
  e = error_of(std::string(pca).replace(pca.find("%s"), 2, ", oscillator_calibration: 1.5"));
  EXPECT_NE(e.find("oscillator_calibration"), std::string::npos) << e;
  // Pulse widths on an I2C throttle ESC mean nothing: refused.
  e = error_of(
      tgy_yaml().replace(tgy_yaml().find("address: 0x2c"), 13, "address: 0x2c, max_us: 1900"));
  EXPECT_NE(e.find("escs[3].max_us: unknown key"), std::string::npos) << e;
  // i2c_tgy needs its section (the bus).
  e = error_of(
      "vehicle: rov4.yaml\nbackend: i2c_tgy\nescs:\n  - {name: front_right, address: 0x29}\n");
  EXPECT_NE(e.find("i2c_tgy"), std::string::npos) << e;
}

TEST(EscConfig, HardwareBackendWithoutTheBusSaysWhatToCheck) {
  auto c = parse_config(tgy_yaml());
  c.tgy.bus = "/dev/i2c-99";
  try {
    esc::make_backend(c);
    FAIL() << "opened a bus that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cannot open I2C bus /dev/i2c-99"), std::string::npos) << m;
    EXPECT_NE(m.find("i2c-dev"), std::string::npos) << m;
  }
}

TEST(EscConfig, LinuxTransportRefusesSomethingThatIsNotAnI2cAdapter) {
  // The real i2c-dev code, on a device node that exists but is not an adapter: I2C_FUNCS fails.
  try {
    i2c::LinuxI2c bus("/dev/null");
    FAIL() << "accepted /dev/null as an I2C adapter";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/null is not an i2c-dev adapter"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tiller::test
