# (owner: study) `legkit study fusion`
