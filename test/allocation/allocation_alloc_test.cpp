// Nothing on the allocation call path touches the heap: every preset x every strategy (direction
// preserving, prioritised, clip; the tables' own normalisation), unsaturated and saturated
// wrenches, manual sticks, invalid input (neutral), counted by replacing the global operator
// new in this binary (the presets and the one-group 8-thruster ROV, test::rov8). Allocators and
// inputs are made before counting starts.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "alloc_count.hpp"
#include "allocation/allocator.hpp"
#include "test_util.hpp"

namespace tiller {
namespace {

struct Case {
  std::string name;
  std::unique_ptr<Allocator> a;
  std::vector<Wrench> wrenches, sticks;
};

int any_saturated(const AllocationResult& r) {
  for (int i = 0; i < r.n; ++i)
    if (r.saturated[static_cast<std::size_t>(i)]) return 1;
  return 0;
}

TEST(AllocationHeap, NoAllocationOnAnyPathOfAnyPreset) {
  std::vector<Case> cases;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vehicle> vehicles;
  for (const auto& name : test::preset_names()) vehicles.push_back(test::preset(name));
  vehicles.push_back(test::rov8(true));  // one group, two spare directions
  for (const Vehicle& base : vehicles) {
    const std::string& name = base.name;
    for (Strategy s : {Strategy::kDirectionPreserving, Strategy::kPrioritised, Strategy::kClip}) {
      Vehicle v = test::with_strategy(base, s);
      if (v.allocation.has_matrix() && s == Strategy::kPrioritised) continue;
      Case c;
      c.name = name + " " + strategy_name(s);
      c.a = std::make_unique<Allocator>(v);
      for (int k = 0; k < 200; ++k) {
        // Unsaturated, lightly and heavily saturated wrenches; single axes; NaN and too big.
        const double size = k % 4 == 0 ? 0.2 : k % 4 == 1 ? 0.9 : k % 4 == 2 ? 1.5 : 6.0;
        c.wrenches.push_back(test::random_wrench(*c.a, rng, size));
      }
      for (int ax = 0; ax < 6; ++ax)
        for (double m : {-5.0, 5.0})
          c.wrenches.push_back(m * c.a->axis_max(ax, 1) * Wrench::Unit(ax));
      Wrench bad = Wrench::Zero();
      bad(1) = std::numeric_limits<double>::quiet_NaN();
      c.wrenches.push_back(bad);
      bad(1) = 2 * kMaxWrenchComponent;
      c.wrenches.push_back(bad);
      c.wrenches.push_back(Wrench::Zero());
      for (int k = 0; k < 200; ++k) {
        Wrench j = Wrench::Zero();
        for (int ax = 0; ax < 6; ++ax) j(ax) = u(rng) * (k % 2 ? 1.0 : 0.2);
        c.sticks.push_back(j);
      }
      c.sticks.push_back(Wrench::Zero());
      c.sticks.push_back(Wrench::Constant(1.0));
      c.sticks.push_back(Wrench::Constant(2.0));  // invalid: neutral
      cases.push_back(std::move(c));
    }
  }
  AllocationResult r;
  std::vector<long> news(cases.size(), 0);
  std::vector<int> saturated(cases.size(), 0);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const long before = test::allocations();
    int sat = 0;
    for (const Wrench& w : c.wrenches) {
      c.a->allocate(w, r);
      sat += any_saturated(r);
    }
    for (const Wrench& j : c.sticks) {
      c.a->allocate_manual(j, r);
      sat += any_saturated(r);
    }
    c.a->neutral(r);
    news[i] = test::allocations() - before;
    saturated[i] = sat;
  }
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(news[i], 0) << cases[i].name;
    EXPECT_GT(saturated[i], 20) << cases[i].name << ": saturation was exercised";
  }
  EXPECT_EQ(cases.size(), 3 * vehicles.size() - 2);  // tables: no prioritised
}

}  // namespace
}  // namespace tiller
