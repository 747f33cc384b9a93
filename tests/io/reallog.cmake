# New log columns (foot velocity, gt_valid, optional gt velocity, generic joints). Owner: iometrics.
