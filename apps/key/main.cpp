// tiller-key: makes and checks a vehicle's signing key file (docs/safety.md, "Who may command").
//   tiller-key new FILE [--force]   a new random key, written with mode 0600; prints its id
//   tiller-key check FILE           loads it as every process does at start-up; prints its id
// Exit 0 on success, 2 with a message naming the file otherwise.
#include <cstdio>
#include <filesystem>

#include "auth/key.hpp"
#include "runtime/app.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  app::Spec spec{
      "tiller-key",
      "Makes (new FILE) or checks (check FILE) a vehicle's message-signing key file.",
      "",
      {{"force", "", "new: replace an existing key file (every process needs the new one)", ""}}};
  spec.arguments = "new FILE | check FILE";
  spec.commands = {{"new", 1}, {"check", 1}};
  spec.takes_config = false;
  spec.takes_lcm_url = false;
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main("tiller-key", [&] {
    const auto& p = args.positional;
    if (p.size() != 2 || (p[0] != "new" && p[0] != "check")) {
      std::fputs("usage: tiller-key new FILE [--force] | tiller-key check FILE (see --help)\n",
                 stderr);
      return 2;
    }
    const std::string& file = p[1];
    if (p[0] == "new") {
      const auto dir = std::filesystem::path(file).parent_path();
      if (!dir.empty()) std::filesystem::create_directories(dir);
      const auth::Key key = auth::generate_key();
      auth::write_key_file(file, key, args.flag("force"));
      std::printf("tiller-key: wrote %s (mode 0600), key id %s\n", file.c_str(),
                  auth::key_id_hex(key.id).c_str());
      return 0;
    }
    const auth::Key key = auth::load_key_file(file);
    std::printf("tiller-key: %s is a valid key file, key id %s\n", file.c_str(),
                auth::key_id_hex(key.id).c_str());
    return 0;
  });
}
