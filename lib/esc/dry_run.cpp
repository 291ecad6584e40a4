#include "esc/dry_run.hpp"

#include <algorithm>
#include <cstring>

#include "esc/backend.hpp"

namespace tiller::esc {

DryRunTransport::DryRunTransport(std::FILE* out, bool every_cycle)
    : out_(out ? out : stdout), every_cycle_(every_cycle), last_(128 * 256) {
  for (auto& l : last_) l[0] = 0xFF;  // length byte 0xFF: nothing written yet
}

void DryRunTransport::add_tgy(std::uint8_t addr) {
  devices_.push_back(std::make_unique<fake::TgyEscModel>());
  bus_.attach(addr, devices_.back().get());
}

void DryRunTransport::add_pca9685(std::uint8_t addr) {
  devices_.push_back(std::make_unique<fake::Pca9685Model>());
  bus_.attach(addr, devices_.back().get());
}

bool DryRunTransport::changed(std::uint8_t addr, const std::uint8_t* d, std::size_t n) {
  if (every_cycle_ || n == 0 || n > 8) return true;
  // One slot per (address, register = first byte written).
  auto& l = last_[static_cast<std::size_t>(addr & 0x7F) * 256 + d[0]];
  const bool same = l[0] == n && std::memcmp(&l[1], d, n) == 0;
  l[0] = static_cast<std::uint8_t>(n);
  std::memcpy(&l[1], d, n);
  return !same;
}

void DryRunTransport::print(std::uint8_t addr, const char* what, const std::uint8_t* w,
                            std::size_t wn, const std::uint8_t* r, std::size_t rn, int err) {
  std::fprintf(out_, "dry-run %.6f s 0x%02x %s", to_seconds(now_), addr, what);
  for (std::size_t k = 0; k < wn; ++k) std::fprintf(out_, " %02x", w[k]);
  if (r) {
    std::fprintf(out_, " ->");
    for (std::size_t k = 0; k < rn; ++k) std::fprintf(out_, " %02x", r[k]);
  }
  if (err) std::fprintf(out_, " FAILED %s", i2c::describe_errno(err).c_str());
  std::fputc('\n', out_);
  std::fflush(out_);
}

int DryRunTransport::write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) {
  const int err = bus_.write(addr, data, n);
  if (changed(addr, data, n)) print(addr, "write", data, n, nullptr, 0, err);
  return err;
}

int DryRunTransport::write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn,
                                std::uint8_t* r, std::size_t rn) {
  const int err = bus_.write_read(addr, w, wn, r, rn);
  if (every_cycle_) print(addr, "write-read", w, wn, r, rn, err);
  return err;
}

void DryRunTransport::wait_us(std::int64_t us) {
  bus_.wait_us(us);
  std::fprintf(out_, "dry-run %.6f s wait %lld us\n", to_seconds(now_), static_cast<long long>(us));
  now_ += us;
}

void DryRunTransport::set_time(TimeUs now) {
  now_ = std::max(now_, now);
  bus_.set_time(now);
}

}  // namespace tiller::esc
