#(owner : factors) — see estimation / fusion / CMakeLists.txt
#Leg - odometry preintegration and the fixed - lag smoother's Ceres factors (IMU, leg odometry,
#exteroceptive pose, bias random walk) with analytic Jacobians.The rotation blocks' ambient
#Jacobians are written in closed form(fusion::ambientJacobian), so the library needs Ceres's
#cost - function headers only; lie::ceres's SO3Manifold is what moves those blocks in the solver.
add_library(legkit_fusion_factors STATIC leg_preintegration.cpp factors.cpp)
    target_include_directories(legkit_fusion_factors PUBLIC ${PROJECT_SOURCE_DIR})
        target_link_libraries(
            legkit_fusion_factors PUBLIC Ceres::ceres legkit_imu lie::lie Eigen3::Eigen)
