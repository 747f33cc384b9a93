# (owner: smoother) — see estimation/fusion/CMakeLists.txt
# legkit_fusion_smoother: the fixed-lag smoother on Ceres (section 57.8, tight coupling):
# keyframes in a 2 s window, IMU and leg-odometry preintegration factors, poses at their stamps,
# and the marginalisation of states leaving the window into a linear (Schur-complement) prior.
add_library(legkit_fusion_smoother STATIC marginalization.cpp fixed_lag_smoother.cpp)
target_include_directories(legkit_fusion_smoother PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_fusion_smoother
  PUBLIC legkit_fusion_factors legkit_estimation legkit_leg_odometry legkit_imu lie::ceres
         Ceres::ceres Eigen3::Eigen)
