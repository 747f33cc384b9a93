# A robot from its own URDF or MJCF through MuJoCo's kinematics (model/mujoco_kinematics.hpp) and the Go2 behind the same LegKinematics interface. Owner: robot.
# The Go2 behind LegKinematics needs no MuJoCo: part of legkit_model.
target_sources(legkit_model PRIVATE
  ${CMAKE_CURRENT_SOURCE_DIR}/leg_kinematics.hpp
  ${CMAKE_CURRENT_SOURCE_DIR}/quadruped_leg_kinematics.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/quadruped_leg_kinematics.hpp)

# legkit_mujoco_kinematics: a URDF or MJCF robot's legs through MuJoCo (MujocoLegKinematics).
add_library(legkit_mujoco_kinematics STATIC
  mujoco_kinematics.cpp
  mujoco_kinematics.hpp)
target_link_libraries(legkit_mujoco_kinematics PUBLIC legkit_mujoco)

# The time for four feet through both implementations (bench/bench_leg_kinematics.cpp).
if(LEGKIT_BUILD_BENCH)
  find_package(benchmark REQUIRED)
  add_executable(bench_leg_kinematics ${PROJECT_SOURCE_DIR}/bench/bench_leg_kinematics.cpp)
  target_link_libraries(bench_leg_kinematics PRIVATE legkit_mujoco_kinematics
                                                     benchmark::benchmark_main)
  set_target_properties(bench_leg_kinematics PROPERTIES RUNTIME_OUTPUT_DIRECTORY
                                                        ${PROJECT_BINARY_DIR}/bench)
endif()
