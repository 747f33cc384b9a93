# Metrics on real data. Owner: iometrics.
