# URDF/MJCF robots. Owner: robot.
