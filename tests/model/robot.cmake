# URDF/MJCF robots. Owner: robot.
legkit_add_test(test_model_leg_kinematics SOURCES leg_kinematics_test.cpp
                LIBS legkit_mujoco_kinematics LABELS "57.11")
