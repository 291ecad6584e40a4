// tiller-launch and message signing (docs/safety.md, "Who may command"): the launch file's
// key_file, require_signed and auth_window_s reach every process (TILLER_KEY_FILE absolute,
// TILLER_REQUIRE_SIGNED, TILLER_AUTH_WINDOW_S); a missing, malformed or group/world-readable
// key stops the launch before anything starts (exit 2, naming the launch file, the line and the
// key file); create_key makes a missing key with mode 0600; require_signed needs a key_file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "auth/key.hpp"
#include "core/config.hpp"
#include "launch/launch_file.hpp"

namespace tiller::launch {
namespace {

namespace fs = std::filesystem;

struct LaunchRun {
  fs::path dir = fs::temp_directory_path() / ("tiller-launch-sign-" + std::to_string(::getpid()));
  LaunchRun() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~LaunchRun() { fs::remove_all(dir); }
  // Writes the launch file (key settings + one process that prints what it was given), runs it.
  int launch(const std::string& key_settings, std::string& out) const {
    std::ofstream(dir / "run.yaml")
        << "name: sign\nroot: .\nends_with: show\n"
        << key_settings
        << "processes:\n  - name: show\n    command: sh\n    args: [-c, 'echo "
           "\"key=$TILLER_KEY_FILE require=$TILLER_REQUIRE_SIGNED "
           "window=$TILLER_AUTH_WINDOW_S\"']\n";
    const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-launch " +
                            (dir / "run.yaml").string() + " --no-log --status-file " +
                            (dir / "status").string() + " > " + (dir / "out.txt").string() +
                            " 2>&1";
    const int st = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(dir / "out.txt").rdbuf();
    out = ss.str();
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
};

TEST(LaunchSigning, SettingsReachEveryProcess) {
  LaunchRun r;
  auth::write_key_file((r.dir / "v.key").string(), auth::generate_key(), false);
  std::string out;
  ASSERT_EQ(r.launch("key_file: v.key\nrequire_signed: true\nauth_window_s: 0.5\n", out), 0) << out;
  const std::string abs = fs::canonical(r.dir / "v.key").string();
  EXPECT_NE(out.find("key=" + abs + " require=1 window=0.5"), std::string::npos) << out;
  EXPECT_NE(out.find("signing: key " + abs + ", unsigned input refused"), std::string::npos) << out;
  // Without a key file: no signing, and the children are told so.
  ASSERT_EQ(r.launch("", out), 0) << out;
  EXPECT_NE(out.find("key= require=0 window=1"), std::string::npos) << out;
  EXPECT_NE(out.find("WARNING: signing off (no key_file)"), std::string::npos) << out;
}

// Issue 30, scenario 1: signing is the default. With a key_file, require_signed defaults to
// true; require_signed: false without allow_unsigned: true is refused before anything starts,
// naming the file, the line and the key; with it, the launcher warns at start. A key_file
// fallback may use $XDG_CONFIG_HOME (else $HOME/.config), where create_key makes the key.
TEST(LaunchSigning, SigningIsTheDefaultAndUnsignedMustBeMeant) {
  LaunchRun r;
  auth::write_key_file((r.dir / "v.key").string(), auth::generate_key(), false);
  std::string out;
  ASSERT_EQ(r.launch("key_file: v.key\n", out), 0) << out;
  EXPECT_NE(out.find("require=1"), std::string::npos) << out;
  EXPECT_EQ(r.launch("key_file: v.key\nrequire_signed: false\n", out), 2) << out;
  EXPECT_NE(out.find("run.yaml:5: require_signed: expected true (false lets anyone on the "
                     "network command the vehicle; if that is meant, say allow_unsigned: true"),
            std::string::npos)
      << out;
  ASSERT_EQ(r.launch("key_file: v.key\nrequire_signed: false\nallow_unsigned: true\n", out), 0)
      << out;
  EXPECT_NE(out.find("require=0"), std::string::npos) << out;
  EXPECT_NE(out.find("WARNING: unsigned input accepted (allow_unsigned: true)"), std::string::npos)
      << out;
  // The shipped simulator files' form: the key made on first use outside the repository.
  const fs::path xdg = r.dir / "xdg";
  ::setenv("XDG_CONFIG_HOME", xdg.c_str(), 1);
  ::unsetenv("TILLER_KEY_FILE");
  ASSERT_EQ(
      r.launch("key_file: ${TILLER_KEY_FILE:-$XDG_CONFIG_HOME/tiller/sim.key}\ncreate_key: true\n",
               out),
      0)
      << out;
  const fs::path made = xdg / "tiller" / "sim.key";
  EXPECT_TRUE(fs::exists(made)) << out;
  EXPECT_EQ(fs::status(made).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_NE(out.find("made a new signing key " + made.string()), std::string::npos) << out;
  EXPECT_NE(out.find("key=" + made.string() + " require=1"), std::string::npos) << out;
  ::unsetenv("XDG_CONFIG_HOME");
}

TEST(LaunchSigning, BadKeyFilesStopTheLaunchNamingTheFile) {
  LaunchRun r;
  std::string out;
  const std::string missing = (r.dir / "missing.key").string();
  EXPECT_EQ(r.launch("key_file: missing.key\nrequire_signed: true\n", out), 2) << out;
  EXPECT_NE(out.find("run.yaml:4: key_file: key file '" + missing + "': No such file"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("key="), std::string::npos) << "a process started: " << out;

  const std::string open = (r.dir / "open.key").string();
  auth::write_key_file(open, auth::generate_key(), false);
  ::chmod(open.c_str(), 0644);
  EXPECT_EQ(r.launch("key_file: open.key\n", out), 2) << out;
  EXPECT_NE(
      out.find("key file '" + open + "': readable or writable by group or others (mode 0644)"),
      std::string::npos)
      << out;

  std::ofstream(r.dir / "bad.key") << "0123\n";
  ::chmod((r.dir / "bad.key").c_str(), 0600);
  EXPECT_EQ(r.launch("key_file: bad.key\n", out), 2) << out;
  EXPECT_NE(out.find("bad.key': malformed"), std::string::npos) << out;
}

TEST(LaunchSigning, CreateKeyMakesAPrivateKeyOnce) {
  LaunchRun r;
  std::string out;
  ASSERT_EQ(r.launch("key_file: keys/sim.key\ncreate_key: true\nrequire_signed: true\n", out), 0)
      << out;
  const fs::path key = r.dir / "keys" / "sim.key";
  EXPECT_NE(out.find("made a new signing key " + key.string()), std::string::npos) << out;
  struct stat st {};
  ASSERT_EQ(::stat(key.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const auth::Key first = auth::load_key_file(key.string());
  ASSERT_EQ(r.launch("key_file: keys/sim.key\ncreate_key: true\nrequire_signed: true\n", out), 0);
  EXPECT_EQ(out.find("made a new signing key"), std::string::npos) << out;
  EXPECT_EQ(auth::load_key_file(key.string()).bytes, first.bytes);
}

TEST(LaunchSigning, RequireSignedNeedsAKeyFile) {
  const auto v = config::Value::parse(
      "name: x\nrequire_signed: true\nprocesses:\n  - {name: a, command: sh}\n", "x.yaml");
  try {
    load_launch(v, ".");
    FAIL() << "accepted require_signed without key_file";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("require_signed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("key_file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tiller::launch
