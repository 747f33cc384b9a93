# (owner: study)
