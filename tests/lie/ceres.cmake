# (owner: lieceres) lie::ceres, the Ceres manifolds of lie/, checked with Ceres's own manifold
# test helpers (ceres/manifold_test_utils.h), which are GoogleTest + GoogleMock matchers: this one
# test program uses Debian's GoogleTest / GoogleMock (libgmock-dev) instead of Catch2.
find_package(Ceres 2.1 REQUIRED)
find_package(GTest QUIET)
if(NOT TARGET GTest::gmock_main)
  message(FATAL_ERROR "test_lie_ceres needs GoogleMock for Ceres's manifold_test_utils.h: "
                      "install Debian's libgmock-dev (apt-get install libgmock-dev)")
endif()
add_executable(test_lie_ceres ceres_manifold_test.cpp)
target_link_libraries(test_lie_ceres PRIVATE lie::ceres GTest::gmock GTest::gmock_main)
add_test(NAME test_lie_ceres COMMAND test_lie_ceres)
set_tests_properties(test_lie_ceres PROPERTIES LABELS "lie")
