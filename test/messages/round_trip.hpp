// The round trip every message test uses (messages_test.cpp, sensor_messages_test.cpp, one
// executable): encode -> decode -> encode gives the same bytes; a truncated packet and one with a
// wrong type hash do not decode. Each type it sees is recorded in round_tripped(), which the
// run's end compares with lcmtypes/.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::test {

inline std::set<std::string>& round_tripped() {
  static std::set<std::string> s;
  return s;
}

template <class Msg>
Msg round_trip(const Msg& in) {
  round_tripped().insert(Msg::getTypeName());
  const Event e = encode("CH", 1, in);
  EXPECT_EQ(static_cast<int>(e.data.size()), in.getEncodedSize());
  Msg out;
  EXPECT_TRUE(decode(e, out));
  const Event again = encode("CH", 1, out);
  EXPECT_EQ(e.data, again.data);
  // A truncated or corrupted packet must not decode.
  Msg bad;
  EXPECT_LT(bad.decode(e.data.data(), 0, static_cast<int>(e.data.size()) - 1), 0);
  std::vector<std::uint8_t> flipped = e.data;
  flipped[0] ^= 0xFF;  // the type hash comes first
  EXPECT_LT(bad.decode(flipped.data(), 0, static_cast<int>(flipped.size())), 0);
  return out;
}

}  // namespace tiller::test
