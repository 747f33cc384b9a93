"""Speed of legkit.estimators from Python, against the C++ (a script run by hand, not a test):

  PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_estimators.py [build/legkit]

1. the overhead of one Estimator.step() call from Python (InEKF, four stance feet), against the
   C++ step's own time on the same kind of input (us_per_step of a whole-log run);
2. a 60 s, 1 kHz log through the InEKF: read + run in Python against `legkit run --log` on the
   same file with the same settings (both read the CSV; the C++ run also writes its outputs).
"""
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

import legkit

est = legkit.estimators
legkit_exe = sys.argv[1] if len(sys.argv) > 1 else "build/legkit"

# 1. step() from Python.
e = est.make("invariant-ekf")
e.reset(est.EstimateSample())
feet = [est.ContactMeasurement(k, np.array([0.19 * s, 0.11 * r, -0.3]), 1e-6 * np.eye(3))
        for k, (s, r) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)])]
gyro, acc = np.zeros(3), np.array([0.0, 0.0, 9.81])
n = 20000
start = time.perf_counter()
for k in range(n):
    e.step(k * 1e-3, 1e-3 if k else 0.0, gyro, acc, feet)
per_step = (time.perf_counter() - start) / n * 1e6
contacts_built = time.perf_counter()
for k in range(n):
    [est.ContactMeasurement(f.foot, f.p_body, f.cov) for f in feet]
build = (time.perf_counter() - contacts_built) / n * 1e6
print(f"InEKF step() from Python, 4 feet: {per_step:.2f} us per call "
      f"(building 4 ContactMeasurement objects each call would add {build:.2f} us)")

# 2. A whole log.
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    log = legkit.sim.simulate("trot", duration=60.0)
    legkit.io.write_log(str(tmp / "trot.csv"), log)
    yaml = "estimators: [invariant-ekf]\n"
    (tmp / "s.yaml").write_text(yaml)
    settings = est.settings_from_yaml(yaml)
    best_py, best_cpp = float("inf"), float("inf")
    for _ in range(3):
        start = time.perf_counter()
        run = est.run(legkit.io.read_log(str(tmp / "trot.csv")), settings)["invariant-ekf"]
        best_py = min(best_py, time.perf_counter() - start)
        start = time.perf_counter()
        subprocess.run([legkit_exe, "run", "--log", str(tmp / "trot.csv"), "--config",
                        str(tmp / "s.yaml"), "--no-plots", "--out", str(tmp / "out")], check=True,
                       capture_output=True)
        best_cpp = min(best_cpp, time.perf_counter() - start)
    print(f"60 s 1 kHz log, InEKF, read + run: Python {best_py:.3f} s, `legkit run` {best_cpp:.3f} s "
          f"(ratio {best_py / best_cpp:.2f}; best of 3); C++ step {run['us_per_step']:.2f} us")
