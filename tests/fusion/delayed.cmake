# (owner: delayed)
