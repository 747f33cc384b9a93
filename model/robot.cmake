# A robot from its own URDF or MJCF through MuJoCo's kinematics (model/mujoco_kinematics.hpp) and the Go2 behind the same LegKinematics interface. Owner: robot.
