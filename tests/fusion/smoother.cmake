# (owner: smoother)
# The fixed-lag smoother: marginalisation on small problems (exact marginal on a linear-Gaussian
# problem, first-order agreement on a nonlinear one with a manifold block).
legkit_add_test(test_smoother_marginalization
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/smoother_marginalization_test.cpp
  LIBS legkit_fusion_smoother
  LABELS "fusion;57.8")

# The smoother on the simulator's analytic trot with simulated poses: tracking, a bounded window,
# old poses counted, Monte Carlo NEES of the newest keyframe, the legs' velocity bias.
legkit_add_test(test_smoother_trot
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/smoother_trot_test.cpp
  LIBS legkit_fusion_smoother legkit_fusion_extero legkit_sim legkit_estimation
  LABELS "fusion;57.8")
