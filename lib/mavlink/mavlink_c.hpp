// The MAVLink 2 C library, generated at build time from the official XML (common.xml and its
// includes, third_party/mavlink/README.md) by the official generator: every message's struct,
// pack and decode functions, the CRC_EXTRA table and the frame parser. Include this header, never
// the generated ones directly, so the settings below hold everywhere:
//   * MAVLINK_NO_SIGN_PACKET, MAVLINK_NO_SIGNATURE_CHECK: the library's own SHA-256 is never
//     used; frames are signed and checked with libsodium (mavlink/signing.hpp);
//   * no global channel state is used: lib/mavlink calls only the *_status and *_buffer
//     functions, with a mavlink_status_t of its own per link.
#pragma once

#define MAVLINK_NO_SIGN_PACKET
#define MAVLINK_NO_SIGNATURE_CHECK
#include <common/mavlink.h>
