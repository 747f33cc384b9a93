# (owner: factors)
