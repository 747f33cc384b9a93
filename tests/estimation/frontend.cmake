# IMU extrinsic and foot velocities in the front end. Owner: frontend.
# The IMU-to-base extrinsic: frame maps, the front end's feet, a trot logged by an offset IMU.
legkit_add_test(test_frontend_extrinsic SOURCES frontend_extrinsic_test.cpp
                LIBS legkit_contact_pipeline legkit_estimators legkit_eval legkit_sim LABELS "57.11;extrinsic")
# Foot velocities (columns, the differentiator against J dq), leg odometry on nothing, generic
# joints through a LegKinematics.
legkit_add_test(test_frontend_feet SOURCES frontend_feet_test.cpp
                LIBS legkit_contact_pipeline legkit_estimators legkit_eval legkit_sim
                LABELS "57.11;frontend")
