// tiller-mavlink's config loader (mavlink/mavlink_config.hpp).
#include "mavlink/mavlink_config.hpp"

#include <algorithm>
#include <iterator>

#include <sodium.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "auth/key.hpp"
#include "core/config_files.hpp"

namespace tiller::mavlink {

namespace {

std::string resolve(const std::string& dir, const std::string& path) {
  return path.empty() || path[0] == '/' || dir.empty() ? path : dir + "/" + path;
}

// QGroundControl's way: the secret is SHA-256 of the passphrase (its text, trailing newline
// dropped). The file must be readable by its owner only, as a key file.
Secret passphrase_secret(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::runtime_error("passphrase file '" + path + "': cannot read it");
  if ((st.st_mode & 077) != 0)
    throw std::runtime_error("passphrase file '" + path +
                             "': readable or writable by group or others (chmod 600 it)");
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  std::string text = ss.str();
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  if (text.empty()) throw std::runtime_error("passphrase file '" + path + "': empty");
  Secret s{};
  crypto_hash_sha256(s.data(), reinterpret_cast<const unsigned char*>(text.data()), text.size());
  return s;
}

}  // namespace

Secret vehicle_secret(const std::array<std::uint8_t, 32>& vehicle_key) {
  static constexpr char kText[] = "tiller mavlink signing v1";
  Secret s{};
  crypto_generichash(s.data(), s.size(), reinterpret_cast<const unsigned char*>(kText),
                     sizeof kText - 1, vehicle_key.data(), vehicle_key.size());
  return s;
}

MavlinkConfig load_mavlink(const config::Value& root, const std::string& dir) {
  MavlinkConfig c;
  MavlinkParams& p = c.node;
  p.period = from_hz(root.number_or("rate_hz", 50.0, {10.0, 200.0}));
  p.system_id = static_cast<std::uint8_t>(root.integer_or("system_id", 1, 1, 254));
  p.component_id = static_cast<std::uint8_t>(root.integer_or("component_id", 1, 1, 254));
  p.submarine =
      root.choice_or("vehicle_type", "surface_boat", {"surface_boat", "submarine"}) == "submarine";
  p.station = root.string_or("station", "");
  if (p.station.size() > 64) root.at("station").fail("a station id of at most 64 characters");
  for (std::size_t i = 0; i < kParamCount; ++i) p.params[i] = kParams[i].fallback;
  p.params[kSysidMygcs] = static_cast<double>(root.integer_or("gcs_system_id", 255, 1, 255));
  if (auto m = root.find("manual_control")) {
    for (std::size_t i : {kManGain, kManDeadzone, kManTimeout, kManYawGain}) {
      const std::string key = std::string(kParams[i].key).substr(15);  // after "manual_control."
      p.params[i] = m->number_or(key, kParams[i].fallback, {kParams[i].min, kParams[i].max});
    }
    p.z_centre = m->number_or("z_centre", 500.0, {-1000.0, 1000.0});
  }
  if (auto cc = root.find("control_config")) {
    const std::string file = config::resolve_near(cc->as_string(), root.file());
    try {
      p.gains = load_gain_params(file);
    } catch (const std::exception& e) {
      cc->fail(std::string("a control config (config/control/<vehicle>.yaml) the controllers "
                           "accept: ") +
               e.what());
    }
  }
  p.mission_retry = from_seconds(root.number_or("mission_retry_s", 1.5, {0.1, 10.0}));
  if (auto s = root.find("signing")) {
    const auto kf = s->find("key_file");
    const auto pf = s->find("passphrase_file");
    p.secret_from_vehicle_key = s->boolean_or("vehicle_key", false);
    if ((kf ? 1 : 0) + (pf ? 1 : 0) + (p.secret_from_vehicle_key ? 1 : 0) != 1)
      s->fail(
          "one of key_file: FILE (tiller-key new FILE), passphrase_file: FILE or "
          "vehicle_key: true");
    if (kf) {
      p.secret_file = resolve(dir, kf->as_string());
      p.secret = auth::load_key_file(p.secret_file).bytes;
    }
    if (pf) p.secret = passphrase_secret(resolve(dir, pf->as_string()));
    p.require_signed = s->boolean_or("required", true);
  }
  if (auto t = root.find("udp")) {
    c.transport.udp_bind = t->string_or("bind", c.transport.udp_bind);
    c.transport.udp_peer = t->string_or("peer", c.transport.udp_peer);
    for (const char* k : {"bind", "peer"}) {
      const std::string v = t->string_or(k, "x:1");
      const auto colon = v.rfind(':');
      if (colon == std::string::npos || colon == 0 || colon + 1 == v.size())
        t->at(k).fail("ADDRESS:PORT, e.g. 127.0.0.1:14550");
    }
  }
  if (auto s = root.find("serial")) {
    c.transport.serial_device = s->string("device");
    c.transport.serial_baud = static_cast<int>(s->integer_or("baud", 57600, 9600, 921600));
    // The speeds the serial link opens (termios' standard ones): another is a config error here,
    // naming the key, not a failure when the port is opened.
    static constexpr int kBauds[] = {9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600};
    if (std::find(std::begin(kBauds), std::end(kBauds), c.transport.serial_baud) ==
        std::end(kBauds))
      s->at("baud").fail("one of 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600");
  }
  root.check_all_used();
  return c;
}

MavlinkConfig load_mavlink_file(const std::string& path) {
  const auto slash = path.rfind('/');
  return load_mavlink(config::Value::load_file(path),
                      slash == std::string::npos ? "" : path.substr(0, slash));
}

}  // namespace tiller::mavlink
