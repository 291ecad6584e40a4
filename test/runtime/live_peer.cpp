// A peer process for live_test: runs the toy controller node under the live LCM executor.
// Usage: runtime_live_peer LCM_URL
#include <iostream>

#include "echo_node.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: runtime_live_peer LCM_URL\n";
    return 2;
  }
  tiller::test::ToyController node(20'000);
  tiller::LiveExecutor ex(argv[1]);
  ex.add(node);
  return ex.run();
}
