// The common command line of every tiller-<name> program: --help, --config FILE,
// --lcm-url URL, plus program-specific options. Keeps each main() a few lines long.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace tiller::app {

struct Option {
  std::string name;        // long name without dashes, e.g. "vehicle"
  std::string value_name;  // e.g. "FILE"; empty for a flag
  std::string help;
  std::string default_value;
};

struct Spec {
  std::string program;         // e.g. "tiller-mixer"
  std::string summary;         // one line: what it does
  std::string default_config;  // relative to the source tree's config/, may be empty
  std::vector<Option> options;
};

struct Args {
  std::string config;                         // path to the YAML config
  std::string lcm_url;                        // LCM URL (TTL 0 unless given)
  std::map<std::string, std::string> values;  // program-specific options (flags: "1")
  std::vector<std::string> positional;
  const std::string& get(const std::string& name) const;
  bool flag(const std::string& name) const;
};

// Parses argv; prints usage and exits 0 on --help, exits 2 with a message on bad usage.
Args parse(int argc, char** argv, const Spec& spec);

// Runs body(); a config or start-up error is printed as "<program>: <message>" and gives 2.
int guarded_main(const std::string& program, const std::function<int()>& body);

}  // namespace tiller::app
