// tiller-cockpit: the browser cockpit. Serves the page over HTTP and bridges LCM to it over a
// WebSocket (lib/cockpit: docs/reference/cockpit-api.md); commands from the page need the token.
#include <unistd.h>

#include <cstdio>

#include "cockpit/cockpit_config.hpp"
#include "cockpit/cockpit_node.hpp"
#include "cockpit/files.hpp"
#include "cockpit/server.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-cockpit",
      "the browser cockpit: the vehicle's state live, and commands (with the token) from the page",
      "config/cockpit/usv_sim.yaml",
      {{"listen", "ADDRESS:PORT", "override the config's listen (default 127.0.0.1:8088)", ""},
       {"processes", "A,B,...", "override the config's processes (the heartbeats shown)", ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    cockpit::CockpitConfig cfg = cockpit::load_cockpit_file(args.config);
    if (!args.get("listen").empty()) cfg.server.listen = args.get("listen");
    if (!args.get("processes").empty())
      cfg.node.processes = cockpit::split_list(args.get("processes"));
    if (cfg.node.station.empty()) {
      char host[256] = {};
      cfg.node.station =
          std::string("cockpit@") + (gethostname(host, sizeof host - 1) == 0 ? host : "");
    }
    const std::string token = cfg.server.token.empty()
                                  ? cockpit::load_or_create_token(cfg.server.token_file)
                                  : cfg.server.token;
    cockpit::CockpitNode node(cfg.node, token, &cockpit::load_mission_text);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    cockpit::CockpitServer server(cfg.server, node, ex);
    std::printf("tiller-cockpit: open %s#token=%s\n", server.url().c_str(), token.c_str());
    std::fflush(stdout);
    return ex.run();
  });
}
