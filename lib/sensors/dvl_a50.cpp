#include "sensors/dvl_a50.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/angles.hpp"

namespace tiller::sensors {

namespace {

using json = nlohmann::json;

struct Bad {
  std::string why;
};

double number(const json& j, const char* key, double lo, double hi) {
  const auto it = j.find(key);
  if (it == j.end()) throw Bad{std::string("no ") + key};
  if (!it->is_number()) throw Bad{std::string(key) + ": expected a number"};
  const double v = it->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    throw Bad{std::string(key) + ": out of range (" + std::to_string(v) + ")"};
  return v;
}

bool boolean(const json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) throw Bad{std::string("no ") + key};
  if (!it->is_boolean()) throw Bad{std::string(key) + ": expected true or false"};
  return it->get<bool>();
}

}  // namespace

DvlParsed parse_dvl_line(std::string_view line) {
  DvlParsed out;
  const json j = json::parse(line.begin(), line.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    out.why = "not a JSON object";
    return out;
  }
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) {
    out.why = "no type";
    return out;
  }
  const std::string t = type->get<std::string>();
  try {
    if (t == "velocity") {
      DvlVelocity& v = out.velocity;
      v.velocity = {number(j, "vx", -20, 20), number(j, "vy", -20, 20), number(j, "vz", -20, 20)};
      v.fom = number(j, "fom", 0, 1e3);
      v.altitude = number(j, "altitude", -1e3, 1e4);
      v.bottom_lock = boolean(j, "velocity_valid");
      v.status = static_cast<int>(number(j, "status", 0, 1e6));
      v.dt_s = number(j, "time", 0, 1e9) / 1000;
      if (const auto c = j.find("covariance"); c != j.end()) {
        if (!c->is_array() || c->size() != 3) throw Bad{"covariance: expected 3x3"};
        for (std::size_t r = 0; r < 3; ++r) {
          const auto& row = (*c)[r];
          if (!row.is_array() || row.size() != 3) throw Bad{"covariance: expected 3x3"};
          for (std::size_t k = 0; k < 3; ++k) {
            if (!row[k].is_number() || !std::isfinite(row[k].get<double>()))
              throw Bad{"covariance: expected finite numbers"};
            v.covariance[3 * r + k] = row[k].get<double>();
          }
        }
        v.has_covariance = true;
      }
      if (const auto tv = j.find("time_of_validity"); tv != j.end()) {
        if (!tv->is_number_integer() || tv->get<std::int64_t>() < 0)
          throw Bad{"time_of_validity: expected a non-negative integer (us)"};
        v.time_of_validity_us = tv->get<std::int64_t>();
      }
      if (const auto tr = j.find("transducers"); tr != j.end() && tr->is_array()) {
        v.beams_valid = 0;
        for (const auto& b : *tr)
          if (b.is_object() && b.value("beam_valid", false)) ++v.beams_valid;
      }
      out.kind = DvlLine::kVelocity;
    } else if (t == "position_local") {
      DvlDeadReckoning& d = out.dead_reckoning;
      d.ts_s = number(j, "ts", 0, 1e12);
      d.position = {number(j, "x", -1e7, 1e7), number(j, "y", -1e7, 1e7),
                    number(j, "z", -1e7, 1e7)};
      d.std_m = number(j, "std", 0, 1e7);
      d.attitude = {deg_to_rad(number(j, "roll", -360, 360)),
                    deg_to_rad(number(j, "pitch", -360, 360)),
                    deg_to_rad(number(j, "yaw", -360, 360))};
      d.status = static_cast<int>(number(j, "status", 0, 1e6));
      out.kind = DvlLine::kDeadReckoning;
    } else {
      out.kind = DvlLine::kIgnored;
      out.why = t;
    }
  } catch (const Bad& b) {
    out.kind = DvlLine::kInvalid;
    out.why = t + ": " + b.why;
  } catch (const json::exception& e) {  // a mistyped field read with value() (beam_valid: 1)
    out.kind = DvlLine::kInvalid;
    out.why = t + ": " + e.what();
  }
  return out;
}

bool dvl_velocity_usable(const DvlVelocity& v, double max_fom) {
  return v.bottom_lock && v.status == 0 && v.fom <= max_fom;
}

}  // namespace tiller::sensors
