# (owner: lieauto)
