// tiller-nav: the estimator. GNSS, IMU, heading and depth in -> TILLER_ODOMETRY with covariance
// and validity bits. See lib/nav/nav_node.hpp and docs/navigation.md.
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-nav", "Estimates the vehicle's state -> TILLER_ODOMETRY", "config/nav/usv.yaml", {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    nav::NavNode node(nav::load_nav_file(args.config));
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
