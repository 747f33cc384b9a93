# (owner: factors)
# The smoother's factors: analytic Jacobians against central differences through the SO3 Plus,
# zero residuals on a noise-free motion, the leg preintegration's covariance and bias Jacobians.
legkit_add_test(test_fusion_factors_jacobian SOURCES factors_jacobian_test.cpp
                LIBS legkit_fusion_factors LABELS "fusion;57.8")
legkit_add_test(test_fusion_factors_residual SOURCES factors_residual_test.cpp
                LIBS legkit_fusion_factors legkit_sim LABELS "fusion;57.8")
legkit_add_test(test_fusion_factors_leg_preintegration SOURCES factors_leg_preintegration_test.cpp
                LIBS legkit_fusion_factors LABELS "fusion;57.8")
