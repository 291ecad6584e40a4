// Compiled once to produce test_pch.hpp precompiled (CMakeLists.txt: tiller_test_pch).
