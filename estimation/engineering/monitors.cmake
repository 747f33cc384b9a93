# Section 57.9: sensor-health and covariance monitors (legkit_monitors). Owner: monitors.
