# (owner: factors) — see estimation/fusion/CMakeLists.txt
# Leg-odometry preintegration and the fixed-lag smoother's Ceres factors (IMU, leg odometry,
# exteroceptive pose, bias random walk) with analytic Jacobians; the rotation blocks live on
# lie::ceres's SO3Manifold, whose PlusJacobian maps the tangent Jacobians to ambient ones.
add_library(legkit_fusion_factors STATIC leg_preintegration.cpp factors.cpp)
target_include_directories(legkit_fusion_factors PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_fusion_factors PUBLIC Ceres::ceres lie::ceres legkit_imu Eigen3::Eigen)
