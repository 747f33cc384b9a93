// Include in a test that uses Ceres, AFTER Ceres's headers: Ceres pulls in glog, whose
// CHECK(condition) replaces Catch's CHECK with an abort on the first failure. This gives Catch's
// back, so that a failing check is reported and the test goes on.
#pragma once

#include <catch2/catch.hpp>

#undef CHECK
#define CHECK(...) \
  INTERNAL_CATCH_TEST("CHECK", Catch::ResultDisposition::ContinueOnFailure, __VA_ARGS__)
