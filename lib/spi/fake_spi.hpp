// A fake SPI device node for tests, benchmarks and the bring-up rehearsal (no /dev/spidev* on the
// build machine): FakeSpi implements spi::Transport and hands each transfer to one FakeSpiDevice
// (a chip model, e.g. sensors/fake/icm20602_model.hpp). Faults are injected as an errno for N
// transfers or for ever; time comes from set_time()/wait_us(). No allocation in a transfer.
#pragma once

#include <cstdint>
#include <string>

#include "spi/transport.hpp"

namespace tiller::spi {

class FakeSpiDevice {
 public:
  virtual ~FakeSpiDevice() = default;
  // One transfer with the chip selected: tx[0..n) in, rx[0..n) out (rx may be null).
  virtual void on_transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n, TimeUs now) = 0;
  virtual void advance(TimeUs now) { (void)now; }
};

class FakeSpi : public Transport {
 public:
  explicit FakeSpi(std::string name = "fake-spi") : name_(std::move(name)) {}
  int transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n) override;
  void wait_us(std::int64_t us) override { set_time(now_ + us); }
  void set_time(TimeUs now) override;
  std::string name() const override { return name_; }

  void attach(FakeSpiDevice* d) { device_ = d; }  // not owned; nullptr = nothing wired
  // The next `count` transfers fail with err (count < 0: until clear_fault()).
  void fail(int err, int count = -1) {
    fault_err_ = err;
    fault_count_ = count;
  }
  void clear_fault() { fault_count_ = 0; }
  std::int64_t transfers() const { return transfers_; }
  TimeUs now() const { return now_; }

 private:
  std::string name_;
  FakeSpiDevice* device_ = nullptr;
  int fault_err_ = 0, fault_count_ = 0;
  std::int64_t transfers_ = 0;
  TimeUs now_ = 0;
};

}  // namespace tiller::spi
