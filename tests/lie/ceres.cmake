# (owner: lieceres)
