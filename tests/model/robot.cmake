# URDF/MJCF robots. Owner: robot.
legkit_add_test(test_model_leg_kinematics SOURCES leg_kinematics_test.cpp
                LIBS legkit_mujoco_kinematics LABELS "57.11")
legkit_add_test(test_model_urdf_robots SOURCES urdf_robots_test.cpp
                LIBS legkit_mujoco_kinematics LABELS "57.11")

# The shipped robots against orocos-kdl (kdl_parser + urdfdom from Debian, an oracle for this test
# only). kdl_parser's own CMake package needs ROS's ament, so header and library are looked up.
find_path(LEGKIT_KDL_PARSER_INCLUDE kdl_parser/kdl_parser.hpp REQUIRED)
find_library(LEGKIT_KDL_PARSER kdl_parser REQUIRED)
find_library(LEGKIT_OROCOS_KDL orocos-kdl REQUIRED)
legkit_add_test(test_model_urdf_oracle SOURCES urdf_oracle_test.cpp
                LIBS legkit_mujoco_kinematics legkit_settings ${LEGKIT_KDL_PARSER} ${LEGKIT_OROCOS_KDL}
                LABELS "57.11")
target_include_directories(test_model_urdf_oracle PRIVATE ${LEGKIT_KDL_PARSER_INCLUDE})
target_compile_definitions(test_model_urdf_oracle PRIVATE LEGKIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
