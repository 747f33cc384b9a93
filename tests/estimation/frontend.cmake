# IMU extrinsic and foot velocities in the front end. Owner: frontend.
