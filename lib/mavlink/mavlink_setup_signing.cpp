// MavlinkNode's SETUP_SIGNING (256, https://mavlink.io/en/guide/message_signing.html): a station
// gives the vehicle a new 32-byte secret and an initial timestamp (10 us units since 2015). Taken
// only in a frame signed with the current secret (and verified: mavlink/signing.hpp) from the
// station in control (SYSID_MYGCS) for this system; an unsigned one while signing is required
// never gets here (dropped and counted in on_frame, rejected.frame.unsigned); an unsigned one
// otherwise, one from another station, for another system or with an all-zero secret (the spec's
// "signing off", which would open the link to unsigned commands) is refused with a STATUSTEXT
// and counted (rejected.setup_signing). Taken: frames out are signed with it, frames in are
// checked against it (every stream starts again, none older than the initial timestamp), counted
// (signing.key_set), and the secret is given to the key sink (apps/mavlink saves it to
// signing.key_file; the timestamp is not saved: the clock's is newer after a restart).
#include <cstring>

#include "mavlink/mavlink_node.hpp"

namespace tiller::mavlink {

void MavlinkNode::on_setup_signing(const mavlink_message_t& msg, TimeUs now) {
  mavlink_setup_signing_t s;
  mavlink_msg_setup_signing_decode(&msg, &s);
  if (s.target_system != p_.system_id) {
    ++*other_target_;
    return;
  }
  auto refuse = [&](const char* why) {
    reject(*signing_refused_);
    statustext(MAV_SEVERITY_WARNING, std::string("setup signing refused: ") + why, now);
  };
  if (!frame_signed_) {
    refuse("not over a signed link");
    return;
  }
  if (!from_gcs(msg, now)) {
    reject(*signing_refused_);
    return;
  }
  Secret key{};
  std::memcpy(key.data(), s.secret_key, key.size());
  bool zero = true;
  for (std::uint8_t b : key) zero = zero && b == 0;
  if (zero) {
    refuse("an all-zero key would turn signing off");
    return;
  }
  writer_.set_secret(key, s.initial_timestamp);
  checker_->rekey(key, s.initial_timestamp);
  p_.secret = key;
  ++*signing_set_;
  const bool saved = key_sink_ && key_sink_(key);
  statustext(MAV_SEVERITY_NOTICE,
             saved       ? "signing key set and saved"
             : key_sink_ ? "signing key set, NOT saved (see the log)"
                         : "signing key set until the bridge restarts",
             now);
}

}  // namespace tiller::mavlink
