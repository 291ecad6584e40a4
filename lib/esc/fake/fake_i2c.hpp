// A fake I2C bus with models of the devices tiller-esc talks to, for tests, benchmarks and
// the dry-run backend (no /dev/i2c-* exists on the build machine).
//
// FakeI2cBus implements esc::I2cTransport: each 7-bit address may hold a Device; an empty
// address NACKs (ENXIO); faults can be injected per address (any errno, for N transactions or
// for ever). Time comes from set_time()/wait_us() (the backends pass the node's time), and the
// devices advance on it. Transactions can be recorded (exact bytes, for tests); recording is
// off by default so that a cycle allocates nothing.
//
// TgyEscModel: the BlueESC/tgy SIMPLE_I2C register map (see esc/tgy_backend.hpp): register
// pointer set by the first written byte, auto-increment on write and read; the throttle acts
// when its low byte (0x01) arrives; after power-up the ESC runs only once it has heard a zero
// throttle; with no throttle write for `stop_after_us` (4.5 s) it stops and needs a zero again;
// reading 0x02 returns and clears the commutation pulse count; 0x0A reads 0xAB.
// Pca9685Model: MODE1 (RESTART, EXTCLK, AI, SLEEP), MODE2, LEDn ON/OFF, ALL_LED, PRE_SCALE
// (writes ignored unless SLEEP = 1), power-up state asleep (MODE1 0x11, PRE_SCALE 0x1E), the
// oscillator runs 500 us after SLEEP is cleared; pulse_us(ch) is the width on the pin.
#pragma once

#include <array>
#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include "esc/transport.hpp"

namespace tiller::esc::fake {

class Device {
 public:
  virtual ~Device() = default;
  // One write transaction (the bytes after the address). 0 = ACKed, else an errno.
  virtual int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) = 0;
  // One read transaction of n bytes from the register pointer.
  virtual int on_read(std::uint8_t* out, std::size_t n, TimeUs now) = 0;
  // Time passes.
  virtual void advance(TimeUs now) { (void)now; }
};

class TgyEscModel : public Device {
 public:
  TgyEscModel();
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;

  // Model parameters.
  double max_rpm = 3800;  // at full throttle
  int poles = 14;
  TimeUs stop_after_us = 4'500'000;
  double volts = 16.0, amps = 0.5, temperature_c = 25.0;
  std::uint8_t identifier = 0xAB;

  // State.
  std::int16_t throttle() const { return throttle_; }  // last complete throttle written
  std::int16_t output() const { return output_; }      // what the motor does (0 when not armed)
  bool armed() const { return armed_; }
  std::int64_t throttle_writes() const { return throttle_writes_; }
  TimeUs last_throttle_time() const { return last_cmd_; }
  double pulses_pending() const { return pulses_; }
  void power_cycle();

 private:
  std::uint8_t read_reg(std::uint8_t r) const;
  std::uint8_t ptr_ = 0;
  std::uint8_t hi_ = 0;
  std::int16_t throttle_ = 0, output_ = 0;
  bool armed_ = false;
  bool ever_cmd_ = false;
  TimeUs last_cmd_ = 0, last_advance_ = 0;
  bool advanced_ = false;
  double pulses_ = 0;
  std::uint16_t latched_pulses_ = 0;
  std::int64_t throttle_writes_ = 0;
};

class Pca9685Model : public Device {
 public:
  explicit Pca9685Model(double oscillator_hz = 25e6);
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;

  double oscillator_hz;          // the chip's real internal oscillator
  double external_clock_hz = 0;  // what is on EXTCLK, if anything

  std::uint8_t reg(std::uint8_t r) const { return regs_[r]; }
  bool sleeping() const { return (regs_[0] & 0x10) != 0; }
  bool oscillator_running(TimeUs now) const;
  // Pulse width on channel ch (us), 0 when no pulses come out (asleep, not yet settled, off).
  double pulse_us(int ch, TimeUs now) const;
  int off_count(int ch) const;
  double pwm_hz() const;
  std::int64_t prescale_writes_ignored() const { return prescale_ignored_; }
  std::int64_t led_writes() const { return led_writes_; }
  void power_cycle();

 private:
  void write_reg(std::uint8_t r, std::uint8_t v, TimeUs now);
  std::array<std::uint8_t, 256> regs_{};
  std::uint8_t ptr_ = 0;
  TimeUs osc_ready_at_ = 0;
  std::int64_t prescale_ignored_ = 0;
  std::int64_t led_writes_ = 0;
};

// One recorded transaction.
struct Transaction {
  std::uint8_t addr = 0;
  bool read = false;                // write-then-read
  std::vector<std::uint8_t> wrote;  // bytes written
  std::size_t read_n = 0;           // bytes read
  int err = 0;
  TimeUs time = 0;
};

class FakeI2cBus : public I2cTransport {
 public:
  explicit FakeI2cBus(std::string name = "fake-i2c");
  int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) override;
  int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                 std::size_t rn) override;
  int claim(std::uint8_t addr) override { return busy_[addr & 0x7F] ? EBUSY : 0; }
  void wait_us(std::int64_t us) override;
  void set_time(TimeUs now) override;
  std::string name() const override { return name_; }

  // Devices (not owned). detach() = the device is unplugged.
  void attach(std::uint8_t addr, Device* d) { devices_[addr & 0x7F] = d; }
  void detach(std::uint8_t addr) { devices_[addr & 0x7F] = nullptr; }
  // The next `count` transactions to addr fail with err (count < 0: until clear_fault).
  void fail(std::uint8_t addr, int err, int count = -1);
  void clear_fault(std::uint8_t addr) { faults_[addr & 0x7F] = Fault{}; }
  void set_busy(std::uint8_t addr, bool b) { busy_[addr & 0x7F] = b; }

  TimeUs now() const { return now_; }
  std::int64_t waited_us() const { return waited_; }
  std::int64_t transactions() const { return transactions_; }
  // Recording of transactions (off by default).
  void record(bool on) { recording_ = on; }
  std::vector<Transaction>& log() { return log_; }

 private:
  struct Fault {
    int err = 0;
    int count = 0;
  };
  int fault(std::uint8_t addr);
  void note(std::uint8_t addr, bool read, const std::uint8_t* w, std::size_t wn, std::size_t rn,
            int err);
  std::string name_;
  std::array<Device*, 128> devices_{};
  std::array<Fault, 128> faults_{};
  std::array<bool, 128> busy_{};
  TimeUs now_ = 0;
  std::int64_t waited_ = 0, transactions_ = 0;
  bool recording_ = false;
  std::vector<Transaction> log_;
};

}  // namespace tiller::esc::fake
