# URDF/MJCF robots. Owner: robot.
legkit_add_test(test_model_leg_kinematics SOURCES leg_kinematics_test.cpp
                LIBS legkit_mujoco_kinematics LABELS "57.11")
legkit_add_test(test_model_urdf_robots SOURCES urdf_robots_test.cpp
                LIBS legkit_mujoco_kinematics LABELS "57.11")
