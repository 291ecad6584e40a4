// Building blocks of the simulated sensors (lib/sim/sensor_models.hpp): a seeded generator, a
// wandering bias, a sensor's timing (rate, latency, dropouts) and a fixed-size delay line that
// holds samples until their latency has passed. No clock (times are arguments), no heap after
// construction, same seed and same calls: same numbers, bit for bit.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "core/time.hpp"

namespace tiller::sim {

// One sensor's random numbers: each sensor has its own generator (seeded from the simulator's
// seed and the sensor's name), so switching one sensor off leaves the others' noise unchanged.
class SensorRng {
 public:
  explicit SensorRng(std::uint64_t seed) : g_(seed) {}
  double normal() { return normal_(g_); }    // N(0, 1)
  double uniform() { return uniform_(g_); }  // [0, 1)

 private:
  std::mt19937_64 g_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// A bias that wanders: first-order Gauss-Markov (Fossen 2021, eq. 8.22), a random walk pulled
// back to 0 with time constant tau_s, stationary standard deviation std. It starts at a draw of
// N(0, std^2) (a turn-on bias) and moves by the exact discretisation
//   b+ = a b + std sqrt(1 - a^2) n,  a = exp(-dt / tau_s).
// tau_s = 0: the turn-on bias stays constant. std = 0: no bias.
struct BiasParams {
  double std = 0;    // the sensor's unit (m, rad, rad/s, m/s^2, Pa)
  double tau_s = 0;  // s; 0 = constant
};

class Bias {
 public:
  Bias() = default;
  Bias(const BiasParams& p, SensorRng& rng) : p_(p), value_(p.std > 0 ? p.std * rng.normal() : 0) {}
  void step(double dt, SensorRng& rng) {
    if (!(p_.std > 0) || !(p_.tau_s > 0) || !(dt > 0)) return;
    const double a = std::exp(-dt / p_.tau_s);
    value_ = a * value_ + p_.std * std::sqrt(1.0 - a * a) * rng.normal();
  }
  double value() const { return value_; }

 private:
  BiasParams p_;
  double value_ = 0;
};

// When a sensor samples and when its sample arrives.
struct SensorTiming {
  bool enabled = false;
  TimeUs period_us = 100'000;      // 1 / rate; a whole number of simulator steps
  TimeUs latency_us = 0;           // from the sample to its message, < kMaxLatencyPeriods periods
  double dropout_probability = 0;  // each sample is lost with this probability, [0, 1)
  static constexpr int kMaxLatencyPeriods = 14;
};

// Samples waiting for their latency, oldest first: a ring of N slots of Msg assigned in place
// (a message whose strings and arrays keep their size reuses its storage: no allocation).
template <class Msg, int N = SensorTiming::kMaxLatencyPeriods + 2>
class DelayLine {
 public:
  // False (the sample is lost) when N samples are already waiting.
  bool push(const Msg& m, TimeUs release) {
    if (count_ == N) return false;
    const int i = (head_ + count_) % N;
    slot_[static_cast<std::size_t>(i)] = m;
    at_[static_cast<std::size_t>(i)] = release;
    ++count_;
    return true;
  }
  // Hands every sample due at `now` (release <= now) to f, oldest first.
  template <class F>
  void release(TimeUs now, F&& f) {
    while (count_ > 0 && at_[static_cast<std::size_t>(head_)] <= now) {
      f(slot_[static_cast<std::size_t>(head_)]);
      head_ = (head_ + 1) % N;
      --count_;
    }
  }
  int size() const { return count_; }
  // Gives every slot the shape of `m` (its strings and arrays), so that later samples of the same
  // shape are assigned without allocating.
  void reserve_like(const Msg& m) {
    for (auto& s : slot_) s = m;
  }

 private:
  std::array<Msg, N> slot_{};
  std::array<TimeUs, N> at_{};
  int head_ = 0, count_ = 0;
};

}  // namespace tiller::sim
