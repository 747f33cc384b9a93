# Monitors and fault injection. Owner: monitors.
