// The dry-run transport: prints every I2C transaction the real backend would make, and answers
// from the fake device models (esc/fake/fake_i2c.hpp), so a dry run goes through exactly the
// code that drives hardware. Lines look like
//   dry-run 1.230000 s 0x29 write 00 7f ff
//   dry-run 1.230000 s 0x40 write-read fe -> 79
// With every_cycle = false a transaction is printed only when its bytes differ from the last
// transaction to the same address and register (a steady throttle prints once).
#pragma once

#include <array>
#include <cstdio>
#include <memory>
#include <vector>

#include "esc/fake/fake_i2c.hpp"
#include "i2c/transport.hpp"

namespace tiller::esc {

class DryRunTransport : public i2c::Transport {
 public:
  DryRunTransport(std::FILE* out, bool every_cycle);
  int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) override;
  int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                 std::size_t rn) override;
  void wait_us(std::int64_t us) override;
  void set_time(TimeUs now) override;
  std::string name() const override { return "dry-run"; }

  // The models answering (a tgy ESC or a PCA9685 is attached at each configured address).
  i2c::FakeBus& models() { return bus_; }
  void add_tgy(std::uint8_t addr);
  void add_pca9685(std::uint8_t addr);

 private:
  bool changed(std::uint8_t addr, const std::uint8_t* d, std::size_t n);
  void print(std::uint8_t addr, const char* what, const std::uint8_t* w, std::size_t wn,
             const std::uint8_t* r, std::size_t rn, int err);
  std::FILE* out_;
  bool every_cycle_;
  TimeUs now_ = 0;
  i2c::FakeBus bus_{"dry-run"};
  std::vector<std::unique_ptr<i2c::FakeDevice>> devices_;
  // Last bytes written per (7-bit address, first byte = register): [length, up to 8 bytes].
  // Allocated once at construction (128 x 256 slots).
  std::vector<std::array<std::uint8_t, 9>> last_;
};

}  // namespace tiller::esc
