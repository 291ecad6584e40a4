// A fake I2C bus for tests, benchmarks and the ESC's dry-run backend (no /dev/i2c-* exists on
// the build machine).
//
// FakeBus implements i2c::Transport: each 7-bit address may hold a FakeDevice (a model of a
// chip: esc/fake/fake_i2c.hpp for the ESCs and the PCA9685, sensors/fake/ for the sensors); an
// empty address NACKs (ENXIO); faults can be injected per address (any errno, for N
// transactions or for ever). Time comes from set_time()/wait_us() (the drivers pass the node's
// time), and the devices advance on it. Transactions can be recorded (exact bytes, for tests);
// recording is off by default so that a cycle allocates nothing.
#pragma once

#include <array>
#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include "i2c/transport.hpp"

namespace tiller::i2c {

class FakeDevice {
 public:
  virtual ~FakeDevice() = default;
  // One write transaction (the bytes after the address). 0 = ACKed, else an errno.
  virtual int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) = 0;
  // One read transaction of n bytes from the register pointer.
  virtual int on_read(std::uint8_t* out, std::size_t n, TimeUs now) = 0;
  // Time passes.
  virtual void advance(TimeUs now) { (void)now; }
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

class FakeBus : public Transport {
 public:
  explicit FakeBus(std::string name = "fake-i2c");
  int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) override;
  int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                 std::size_t rn) override;
  int claim(std::uint8_t addr) override { return busy_[addr & 0x7F] ? EBUSY : 0; }
  void wait_us(std::int64_t us) override;
  void set_time(TimeUs now) override;
  std::string name() const override { return name_; }

  // Devices (not owned). detach() = the device is unplugged.
  void attach(std::uint8_t addr, FakeDevice* d) { devices_[addr & 0x7F] = d; }
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
  std::array<FakeDevice*, 128> devices_{};
  std::array<Fault, 128> faults_{};
  std::array<bool, 128> busy_{};
  TimeUs now_ = 0;
  std::int64_t waited_ = 0, transactions_ = 0;
  bool recording_ = false;
  std::vector<Transaction> log_;
};

}  // namespace tiller::i2c
