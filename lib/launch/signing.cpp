#include "launch/signing.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "auth/key.hpp"

namespace tiller::launch {

std::map<std::string, std::string> signing_env(const LaunchFile& lf,
                                               const std::map<std::string, std::string>& vars,
                                               const std::string& key_file_override,
                                               std::ostream& out) {
  namespace fs = std::filesystem;
  const std::string where = lf.path + ":" + std::to_string(lf.key_file_line) + ": key_file: ";
  std::string key = key_file_override;
  try {
    // XDG_CONFIG_HOME as the XDG base directory specification defines it: $HOME/.config unset.
    std::map<std::string, std::string> v = vars;
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    if (!(xdg && *xdg) && !v.count("XDG_CONFIG_HOME"))
      v["XDG_CONFIG_HOME"] = std::string(home && *home ? home : "/root") + "/.config";
    if (key.empty()) key = substitute(lf.key_file, v);
  } catch (const std::exception& e) {
    throw std::runtime_error(where + e.what());
  }
  std::map<std::string, std::string> env;
  char window[32];
  std::snprintf(window, sizeof window, "%.6g", lf.auth_window_s);
  // emplace, not operator[] = "literal": GCC 12 at -O3 raises a false -Wrestrict inside
  // std::string::assign for the latter (GCC bugs 105329 / 105651).
  env.emplace("TILLER_AUTH_WINDOW_S", window);
  env.emplace("TILLER_REQUIRE_SIGNED", lf.require_signed ? "1" : "0");
  char clock[32];
  std::snprintf(clock, sizeof clock, "%.6g", lf.clock_offset_s);
  env.emplace("TILLER_CLOCK_OFFSET_S", clock);
  if (key.empty()) return env;  // no signing in this run (require_signed needs a key_file)
  if (key[0] != '/') key = (fs::path(lf.root) / key).lexically_normal().string();
  try {
    if (lf.create_key && key_file_override.empty() && !fs::exists(key)) {
      fs::create_directories(fs::path(key).parent_path());
      try {
        const auth::Key k = auth::generate_key();
        auth::write_key_file(key, k, false);
        out << "tiller-launch: made a new signing key " << key << " (id " << auth::key_id_hex(k.id)
            << "; create_key: true)\n";
      } catch (const std::runtime_error&) {
        if (!fs::exists(key)) throw;  // another run made it first: use that one
      }
    }
    auth::load_key_file(key);
  } catch (const std::exception& e) {
    throw std::runtime_error(where + e.what());
  }
  env["TILLER_KEY_FILE"] = key;
  return env;
}

std::string signing_summary(const LaunchFile& lf, const std::map<std::string, std::string>& env) {
  const auto k = env.find("TILLER_KEY_FILE");
  if (k == env.end())
    return "WARNING: signing off (no key_file): anyone on this network can command the vehicle";
  return "signing: key " + k->second +
         (lf.require_signed ? ", unsigned input refused"
                            : ", WARNING: unsigned input accepted (allow_unsigned: true): anyone "
                              "on this network can command the vehicle");
}

}  // namespace tiller::launch
