// The Water Linked DVL-A50's JSON reports (lib/sensors/dvl_a50.hpp) in the protocol's published
// format (json_v3.1), and malformed ones; the TCP line client (lib/sensors/tcp_lines.hpp)
// against a fake DVL on the loopback of a private network namespace: lines split across
// segments, CR LF, an over-long line dropped and counted, the device closing and coming back.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "sensors/dvl_a50.hpp"
#include "sensors/tcp_lines.hpp"

namespace tiller::sensors {
namespace {

// A velocity report as the protocol documents it (json_v3.1): values of a vehicle moving ahead.
const char* kVelocity =
    R"({"time": 106.3, "vx": 0.1502, "vy": -0.0203, "vz": 0.0041, "fom": 0.0027,)"
    R"( "covariance": [[2.8e-06, -3.1e-07, -1.3e-07], [-3.1e-07, 3.9e-06, 2.1e-07],)"
    R"( [-1.3e-07, 2.1e-07, 5.2e-07]], "altitude": 2.41, "transducers": [)"
    R"({"id": 0, "velocity": 0.068, "distance": 2.78, "rssi": -30.7, "nsd": -89.2, "beam_valid": true},)"
    R"({"id": 1, "velocity": 0.075, "distance": 2.80, "rssi": -31.1, "nsd": -88.6, "beam_valid": true},)"
    R"({"id": 2, "velocity": -0.06, "distance": 2.75, "rssi": -30.2, "nsd": -88.9, "beam_valid": true},)"
    R"({"id": 3, "velocity": -0.07, "distance": 0.0, "rssi": -90.0, "nsd": -89.0, "beam_valid": false}],)"
    R"( "velocity_valid": true, "status": 0, "time_of_validity": 1638191471563017,)"
    R"( "time_of_transmission": 1638191471752336, "format": "json_v3.1", "type": "velocity"})";

TEST(DvlA50, AVelocityReport) {
  const DvlParsed p = parse_dvl_line(kVelocity);
  ASSERT_EQ(p.kind, DvlLine::kVelocity) << p.why;
  const DvlVelocity& v = p.velocity;
  EXPECT_DOUBLE_EQ(v.velocity[0], 0.1502);
  EXPECT_DOUBLE_EQ(v.velocity[1], -0.0203);
  EXPECT_DOUBLE_EQ(v.velocity[2], 0.0041);
  EXPECT_DOUBLE_EQ(v.fom, 0.0027);
  EXPECT_DOUBLE_EQ(v.altitude, 2.41);
  EXPECT_TRUE(v.bottom_lock);
  EXPECT_EQ(v.status, 0);
  EXPECT_DOUBLE_EQ(v.dt_s, 0.1063);
  EXPECT_EQ(v.time_of_validity_us, 1638191471563017);
  EXPECT_EQ(v.beams_valid, 3);
  ASSERT_TRUE(v.has_covariance);
  EXPECT_DOUBLE_EQ(v.covariance[0], 2.8e-06);
  EXPECT_DOUBLE_EQ(v.covariance[5], 2.1e-07);
  EXPECT_DOUBLE_EQ(v.covariance[8], 5.2e-07);
  EXPECT_TRUE(dvl_velocity_usable(v, 0.1));
  EXPECT_FALSE(dvl_velocity_usable(v, 0.001));  // the figure of merit is used
}

TEST(DvlA50, BottomLockLostIsAReportNotAVelocityToUse) {
  const DvlParsed p = parse_dvl_line(
      R"({"time": 250.1, "vx": 0, "vy": 0, "vz": 0, "fom": 2.3, "altitude": -1,)"
      R"( "velocity_valid": false, "status": 0, "format": "json_v2", "type": "velocity"})");
  ASSERT_EQ(p.kind, DvlLine::kVelocity) << p.why;
  EXPECT_FALSE(p.velocity.bottom_lock);
  EXPECT_LT(p.velocity.altitude, 0);
  EXPECT_FALSE(p.velocity.has_covariance);        // json_v2 has none
  EXPECT_EQ(p.velocity.time_of_validity_us, -1);  // nor a time of validity
  EXPECT_FALSE(dvl_velocity_usable(p.velocity, 10));
  // Status 1 (an operational issue, e.g. too hot) is not used either.
  std::string hot = kVelocity;
  hot.replace(hot.find("\"status\": 0"), 11, "\"status\": 1");
  EXPECT_FALSE(dvl_velocity_usable(parse_dvl_line(hot).velocity, 10));
}

TEST(DvlA50, TheDeadReckoningReport) {
  const DvlParsed p = parse_dvl_line(
      R"({"ts": 49056.809, "x": 12.43, "y": 64.09, "z": 1.71, "std": 0.31, "roll": 0.35,)"
      R"( "pitch": -1.64, "yaw": 149.28, "type": "position_local", "status": 0, "format": "json_v3.1"})");
  ASSERT_EQ(p.kind, DvlLine::kDeadReckoning) << p.why;
  EXPECT_DOUBLE_EQ(p.dead_reckoning.ts_s, 49056.809);
  EXPECT_DOUBLE_EQ(p.dead_reckoning.position[1], 64.09);
  EXPECT_DOUBLE_EQ(p.dead_reckoning.std_m, 0.31);
  EXPECT_NEAR(p.dead_reckoning.attitude[2], 149.28 * M_PI / 180, 1e-12);
}

TEST(DvlA50, MalformedAndInvalidLinesSayWhy) {
  struct Case {
    std::string line;
    DvlLine kind;
    const char* why;
  };
  std::string nan_vx = kVelocity;
  nan_vx.replace(nan_vx.find("0.1502"), 6, "\"fast\"");
  std::string fast = kVelocity;
  fast.replace(fast.find("0.1502"), 6, "25.0");
  std::string neg_fom = kVelocity;
  neg_fom.replace(neg_fom.find("0.0027"), 6, "-0.01");
  std::string cov = kVelocity;
  cov.replace(cov.find(", [-1.3e-07, 2.1e-07, 5.2e-07]]"), 31, "]");  // 2 rows
  std::string no_lock = kVelocity;
  no_lock.replace(no_lock.find("\"velocity_valid\": true"), 22, "\"velocity_valid\": 1");
  const std::vector<Case> cases = {
      {"", DvlLine::kMalformed, "not a JSON object"},
      {"{\"vx\": 0.1, ", DvlLine::kMalformed, "not a JSON object"},
      {"[1, 2, 3]", DvlLine::kMalformed, "not a JSON object"},
      {"{\"vx\": 0.1}", DvlLine::kMalformed, "no type"},
      {R"({"type": "velocity", "vy": 0, "vz": 0})", DvlLine::kInvalid, "no vx"},
      {nan_vx, DvlLine::kInvalid, "vx: expected a number"},
      {fast, DvlLine::kInvalid, "vx: out of range"},
      {neg_fom, DvlLine::kInvalid, "fom: out of range"},
      {cov, DvlLine::kInvalid, "covariance"},
      {no_lock, DvlLine::kInvalid, "velocity_valid: expected true or false"},
      {R"({"type": "position_local", "ts": 1, "x": 0, "y": 0})", DvlLine::kInvalid, "no z"},
      {R"({"response_to": "get_config", "success": true, "type": "response"})", DvlLine::kIgnored,
       "response"},
  };
  for (const Case& c : cases) {
    const DvlParsed p = parse_dvl_line(c.line);
    EXPECT_EQ(p.kind, c.kind) << c.line;
    EXPECT_NE(p.why.find(c.why), std::string::npos) << c.line << " -> " << p.why;
  }
}

// A fake DVL: accepts on the loopback, sends `chunks` (each a separate write, lines split across
// them on purpose), closes; then accepts once more and sends `second`.
class FakeDvl {
 public:
  FakeDvl(std::vector<std::string> chunks, std::string second)
      : chunks_(std::move(chunks)), second_(std::move(second)) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    ::listen(fd_, 2);
    thread_ = std::thread([this] {
      int c = ::accept(fd_, nullptr, nullptr);
      for (const auto& s : chunks_) {
        (void)!::send(c, s.data(), s.size(), MSG_NOSIGNAL);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      ::close(c);
      c = ::accept(fd_, nullptr, nullptr);
      (void)!::send(c, second_.data(), second_.size(), MSG_NOSIGNAL);
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      ::close(c);
    });
  }
  ~FakeDvl() {
    thread_.join();
    ::close(fd_);
  }
  int port() const { return port_; }

 private:
  std::vector<std::string> chunks_;
  std::string second_;
  int fd_ = -1, port_ = 0;
  std::thread thread_;
};

TEST(TcpLineClient, LinesFromAFakeDvlThatDropsOutAndReturns) {
  const std::string v = kVelocity;
  const std::string overlong(10000, 'x');
  FakeDvl dvl({v.substr(0, 40), v.substr(40) + "\r\n" + "{\"type\": \"veloc", "ity\"}\n",
               overlong.substr(0, 6000), overlong.substr(6000) + "\n" + v + "\n"},
              v + "\n");
  TcpLineClient c("127.0.0.1", dvl.port(), 8192, 0.05);
  std::vector<std::string> lines;
  for (int i = 0; i < 200 && (lines.size() < 4 || c.connects() < 2); ++i)
    c.poll(20, [&](std::string_view l) { lines.emplace_back(l); });
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], v);  // split across two segments, CR LF removed
  EXPECT_EQ(lines[1], "{\"type\": \"velocity\"}");
  EXPECT_EQ(lines[2], v);  // after the over-long line, which is dropped
  EXPECT_EQ(lines[3], v);  // from the second connection
  EXPECT_EQ(c.overlong(), 1);
  EXPECT_EQ(c.connects(), 2);
  EXPECT_GE(c.disconnects(), 1);
  EXPECT_EQ(parse_dvl_line(lines[1]).kind, DvlLine::kInvalid);
}

TEST(TcpLineClient, NoDeviceKeepsTheCallersRateAndSaysWhy) {
  TcpLineClient c("127.0.0.1", 1, 8192, 0.05);  // nothing listens on port 1
  int lines = 0;
  for (int i = 0; i < 5; ++i) lines += c.poll(10, [](std::string_view) {});
  EXPECT_EQ(lines, 0);
  EXPECT_FALSE(c.connected());
  EXPECT_NE(c.last_error().find("refused"), std::string::npos) << c.last_error();
}

}  // namespace
}  // namespace tiller::sensors
