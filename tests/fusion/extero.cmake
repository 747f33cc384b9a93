# (owner: extero)
