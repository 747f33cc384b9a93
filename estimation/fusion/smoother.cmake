# (owner: smoother) — see estimation/fusion/CMakeLists.txt
# legkit_fusion_smoother: the fixed-lag smoother on Ceres (section 57.8, tight coupling): the
# marginalisation of states leaving the window into a linear (Schur-complement) prior.
add_library(legkit_fusion_smoother STATIC marginalization.cpp)
target_include_directories(legkit_fusion_smoother PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(legkit_fusion_smoother PUBLIC Ceres::ceres Eigen3::Eigen)
