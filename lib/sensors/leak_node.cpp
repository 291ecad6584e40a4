#include "sensors/leak_node.hpp"

#include <cstring>

#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

LeakParams load_leak_params(const config::Value& root) {
  LeakParams p;
  const config::Value probes = root.at("probes", "a list of probes (name, chip, line, active)");
  if (!probes.is_sequence() || probes.size() == 0 || probes.size() > 32)
    probes.fail("a list of 1 to 32 probes");
  for (const config::Value& v : probes.items()) {
    LeakProbe pr;
    pr.name = v.string("name");
    if (pr.name.empty()) v.at("name").fail("a non-empty name");
    for (const LeakProbe& other : p.probes) {
      if (other.name == pr.name) v.at("name").fail("a name no other probe has");
    }
    pr.chip = v.string_or("chip", pr.chip);
    pr.line = static_cast<unsigned>(v.integer("line", 0, 1023));
    for (const LeakProbe& other : p.probes) {
      if (other.chip == pr.chip && other.line == pr.line)
        v.at("line").fail("a line no other probe uses (" + other.name + " has it)");
    }
    pr.active_high = v.choice("active", {"high", "low"}) == "high";
    const std::string bias =
        v.choice_or("bias", "as_is", {"as_is", "pull_up", "pull_down", "disable"});
    pr.bias = bias == "pull_up"     ? Bias::pull_up
              : bias == "pull_down" ? Bias::pull_down
              : bias == "disable"   ? Bias::disable
                                    : Bias::as_is;
    p.probes.push_back(pr);
  }
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {0.1, 1000});
  p.dry_after = from_seconds(root.number_or("dry_after_s", 2.0, {0, 3600}));
  p.channel = root.string_or("channel", p.channel);
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  root.check_all_used();
  return p;
}

LeakParams load_leak_file(const std::string& path) {
  return load_leak_params(config::Value::load_file(path));
}

LeakNode::LeakNode(const LeakParams& p, GpioInputs& gpio)
    : Node("leak", from_hz(p.rate_hz)), p_(p), gpio_(gpio) {
  advertise<leak_t>(p.channel);
  request_failures_ = &counter("gpio.request_failures");
  read_errors_ = &counter("gpio.read_errors");
  wet_events_ = &counter("wet_events");
  rejected_ = &counter("rejected.reading.range");
  const auto n = p.probes.size();
  msg_.n_probes = static_cast<std::int32_t>(n);
  msg_.names.resize(n);
  msg_.wet.assign(n, 1);  // unread: wet (fail safe)
  msg_.readable.assign(n, 0);
  msg_.any_wet = n > 0;
  for (std::size_t i = 0; i < n; ++i) {
    Probe pr;
    pr.cfg = p.probes[i];
    pr.where = "probe " + pr.cfg.name + " (" + pr.cfg.chip + " line " +
               std::to_string(pr.cfg.line) + ", active " + (pr.cfg.active_high ? "high" : "low") +
               ")";
    probes_.push_back(pr);
    msg_.names[i] = pr.cfg.name;
  }
  set_health(heartbeat_t::STATE_FAULT, "not read yet");
}

LeakNode::~LeakNode() {
  for (Probe& pr : probes_)
    if (pr.handle >= 0) gpio_.release(pr.handle);
}

void LeakNode::on_tick(TimeUs now) {
  bool any = false;
  for (std::size_t i = 0; i < probes_.size(); ++i) {
    Probe& pr = probes_[i];
    if (pr.handle < 0 && now >= pr.next_request) {
      pr.error.clear();
      pr.handle = gpio_.request(pr.cfg.chip, pr.cfg.line, pr.cfg.bias, "tiller-leak", pr.error);
      if (pr.handle < 0) {
        ++*request_failures_;
        pr.next_request = now + p_.retry_period;
      }
    }
    int level = -1;
    if (pr.handle >= 0) {
      level = gpio_.read(pr.handle);
      if (level < 0) {
        ++*read_errors_;
        pr.error = "read failed: ";
        pr.error += std::strerror(-level);
        gpio_.release(pr.handle);
        pr.handle = -1;
        pr.next_request = now + p_.retry_period;
      }
    }
    const bool was_wet = msg_.wet[i] && msg_.readable[i];
    if (level < 0) {
      msg_.readable[i] = 0;
      msg_.wet[i] = 1;
    } else {
      msg_.readable[i] = 1;
      const bool active = (level == 1) == pr.cfg.active_high;
      if (active) pr.last_active = now;
      const bool first = msg_.wet[i] && pr.last_active == INT64_MIN;  // never wet, first read
      msg_.wet[i] =
          active || (!first && pr.last_active != INT64_MIN && now - pr.last_active < p_.dry_after);
      if (msg_.wet[i] && !was_wet) ++*wet_events_;
    }
    any = any || msg_.wet[i];
  }
  msg_.any_wet = any;
  msg_.utime = now;
  if (checks::check(msg_) != nullptr) {
    reject(*rejected_);
  } else {
    publish(p_.channel, msg_);
  }
  update_health();
}

void LeakNode::update_health() {
  std::uint64_t key = 0;
  for (std::size_t i = 0; i < probes_.size(); ++i) {
    if (msg_.readable[i]) key |= 1ull << i;
    if (msg_.wet[i]) key |= 1ull << (i + 32);
  }
  bool all_readable = true;
  for (std::size_t i = 0; i < probes_.size(); ++i) all_readable = all_readable && msg_.readable[i];
  if (key != health_key_) {  // built only on a change: a steady state allocates nothing
    health_key_ = key;
    status_.clear();
    for (std::size_t i = 0; i < probes_.size(); ++i) {
      if (!msg_.readable[i]) {
        status_ += (status_.empty() ? "" : "; ") + probes_[i].where + ": " + probes_[i].error;
      }
    }
    std::string wet;
    for (std::size_t i = 0; i < probes_.size(); ++i) {
      if (msg_.readable[i] && msg_.wet[i]) wet += (wet.empty() ? "" : ", ") + probes_[i].cfg.name;
    }
    if (!wet.empty()) status_ += (status_.empty() ? "LEAK: " : "; LEAK: ") + wet + " wet";
    if (status_.empty()) status_ = std::to_string(probes_.size()) + " probes dry";
  }
  set_health(all_readable ? heartbeat_t::STATE_OK : heartbeat_t::STATE_FAULT, status_);
}

}  // namespace tiller::sensors
