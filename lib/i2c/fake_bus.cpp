#include "i2c/fake_bus.hpp"

#include <algorithm>
#include <cerrno>

namespace tiller::i2c {

FakeBus::FakeBus(std::string name) : name_(std::move(name)) {}

void FakeBus::fail(std::uint8_t addr, int err, int count) {
  faults_[addr & 0x7F] = Fault{err, count};
}

int FakeBus::fault(std::uint8_t addr) {
  Fault& f = faults_[addr & 0x7F];
  if (f.count == 0 || f.err == 0) return 0;
  if (f.count > 0) --f.count;
  return f.err;
}

void FakeBus::note(std::uint8_t addr, bool read, const std::uint8_t* w, std::size_t wn,
                   std::size_t rn, int err) {
  ++transactions_;
  if (!recording_) return;
  Transaction t;
  t.addr = addr;
  t.read = read;
  t.wrote.assign(w, w + wn);
  t.read_n = rn;
  t.err = err;
  t.time = now_;
  log_.push_back(std::move(t));
}

int FakeBus::write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) {
  int err = fault(addr);
  if (err == 0) {
    FakeDevice* d = devices_[addr & 0x7F];
    err = d ? d->on_write(data, n, now_) : ENXIO;
  }
  note(addr, false, data, n, 0, err);
  return err;
}

int FakeBus::write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                        std::size_t rn) {
  int err = fault(addr);
  if (err == 0) {
    FakeDevice* d = devices_[addr & 0x7F];
    err = d ? d->on_write(w, wn, now_) : ENXIO;
    if (err == 0) err = d->on_read(r, rn, now_);
  }
  if (err != 0) std::fill(r, r + rn, 0);
  note(addr, true, w, wn, rn, err);
  return err;
}

void FakeBus::set_time(TimeUs now) {
  if (now <= now_) return;
  now_ = now;
  for (FakeDevice* d : devices_) {
    if (d) d->advance(now_);
  }
}

void FakeBus::wait_us(std::int64_t us) {
  waited_ += us;
  set_time(now_ + us);
}

}  // namespace tiller::i2c
