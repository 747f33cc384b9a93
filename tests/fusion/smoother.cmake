# (owner: smoother)
