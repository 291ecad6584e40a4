// The precompiled header of every GoogleTest executable (tiller_test in CMakeLists.txt): the
// third-party and standard headers most tests include, parsed once per build instead of once per
// test file. Only headers from outside the project belong here: a project header in a
// precompiled header would rebuild every test when it changes, and would hide a missing include.
#pragma once

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>
#include <Eigen/Dense>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>
