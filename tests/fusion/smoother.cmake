# (owner: smoother)
# The fixed-lag smoother: marginalisation on small problems (exact marginal on a linear-Gaussian
# problem, first-order agreement on a nonlinear one with a manifold block).
legkit_add_test(test_smoother_marginalization
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/smoother_marginalization_test.cpp
  LIBS legkit_fusion_smoother
  LABELS "fusion;57.8")
