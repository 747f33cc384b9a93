#!/usr/bin/python3
"""The bad-input matrix: about a hundred broken or extreme logs, each run through `legkit run`.

    tools/bad-inputs/matrix.py --legkit build/legkit [--dir DIR] [--keep] [--jobs N] [--verbose]

Every case is made from a short simulated trot (`legkit sim`) by one change, and states what a
correct kit does with it:
  error    the run is refused: exit code 2, nothing estimated, and the message names the file and
           the line (and the column where there is one);
  survive  the run goes through: exit code 0 or 3 (3: an estimator failed or had to recover, and
           says so), every estimate written is finite and physical (|p| < 1e6 m, |v| < 1e3 m/s);
  any      either of the two, cleanly.
Whatever the case: no crash (a signal, or an exit code above 3), no hang (60 s), no Python-style
traceback, and a message of reasonable length (under 2000 characters).

Each case is classified as the other matrices' are (options.py, files.py):
  OK       as stated above;
  SILENT   a run that went through (exit 0 or 3) where a refusal was due, or that wrote an estimate
           that is not finite and physical, or no output;
  UNCLEAR  a refusal that names neither the file nor the line, a message over 2000 characters, or
           a log that should run refused;
  HANG     no answer in 60 s;
  CRASH    a signal, or an exit code above 3.
Prints the cases that are not OK (every case with --verbose) and the counts per class; exits 1
unless every case is OK.
"""
import csv
import io
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

from matrix_report import parser, report

TIMEOUT = 60.0
ROW = 500  # the data row most cases spoil (0-based)


class Log:
    """A log as comment lines, header names and rows of text fields."""

    def __init__(self, path):
        with open(path, newline="") as f:
            lines = f.read().split("\n")
        if lines and lines[-1] == "":
            lines.pop()
        self.comments = [l for l in lines if l.startswith("#")]
        body = [l for l in lines if not l.startswith("#")]
        self.header = body[0].split(",")
        self.rows = [l.split(",") for l in body[1:]]

    def copy(self):
        c = Log.__new__(Log)
        c.comments = list(self.comments)
        c.header = list(self.header)
        c.rows = [list(r) for r in self.rows]
        return c

    def col(self, name):
        return self.header.index(name)

    def set(self, row, name, value):
        self.rows[row][self.col(name)] = value

    def drop_columns(self, predicate):
        keep = [i for i, n in enumerate(self.header) if not predicate(n)]
        self.header = [self.header[i] for i in keep]
        self.rows = [[r[i] for i in keep] for r in self.rows]

    def rename(self, old, new):
        self.header[self.col(old)] = new

    def line_of_row(self, row):  # 1-based file line of data row `row`
        return len(self.comments) + 2 + row

    def text(self, eol="\n"):
        lines = self.comments + [",".join(self.header)] + [",".join(r) for r in self.rows]
        return eol.join(lines) + eol


def feet_only(log, covariance="var"):
    """The same run described by body-frame foot columns instead of joints."""
    log.drop_columns(lambda n: n.startswith(("q_", "dq_", "tau_")))
    for k, leg in enumerate(["FL", "FR", "RL", "RR"]):
        for group in ("force", "contact"):
            if f"{group}_{leg}" in log.header:
                log.rename(f"{group}_{leg}", f"foot{k}_{group}")
    return log


def cases(base, feet_diag, feet_full, no_gt):
    """Yields (name, expectation, contents as bytes, expected line or None)."""
    line = base.line_of_row(ROW)

    def spoil(column, value, log=base, row=ROW):
        c = log.copy()
        c.set(row, column, value)
        return c.text().encode()

    # One bad value in each column group: NaN, inf, text, empty.
    for column in ["t", "gyro_x", "acc_z", "q_FL_0", "dq_RR_2", "tau_FR_1", "force_RL",
                   "contact_FL", "gt_px", "gt_qw", "gt_vz"]:
        for label, value in [("nan", "nan"), ("inf", "inf"), ("text", "abc"), ("empty", "")]:
            yield f"{column}-{label}", "error", spoil(column, value), line
    for column, value in [("gyro_y", "1e400"), ("acc_x", "-1e400"), ("gyro_z", "1e-400"),
                          ("contact_RR", "2"), ("contact_RR", "0.5"), ("contact_FR", "-1"),
                          ("gt_qw", "0.5"), ("gt_qx", "2")]:
        yield f"{column}={value}", "error", spoil(column, value), line
    yield "hex-float", "any", spoil("gyro_x", "0x1p-3"), line
    yield "nul-in-field", "error", spoil("acc_y", "1\x002"), line
    yield "long-field-100kB", "error", spoil("acc_y", "9" * 50 + "x" * 100_000), line
    yield "utf8-in-field", "error", spoil("acc_y", "9.81\u00b5"), line

    # Rows of the wrong length, order of time.
    c = base.copy(); c.rows[ROW] = c.rows[ROW][:-3]
    yield "row-too-short", "error", c.text().encode(), line
    c = base.copy(); c.rows[ROW] = c.rows[ROW] + ["0"]
    yield "row-too-long", "error", c.text().encode(), line
    c = base.copy(); c.rows[ROW] = []
    yield "row-empty", "any", c.text().encode(), None
    c = base.copy(); c.set(ROW, "t", c.rows[ROW - 1][c.col("t")])
    yield "time-repeated", "error", c.text().encode(), line
    c = base.copy(); c.set(ROW, "t", "0")
    yield "time-backwards", "error", c.text().encode(), line
    c = base.copy()
    for r in c.rows[ROW:]:
        r[c.col("t")] = repr(float(r[c.col("t")]) + 10.0)
    yield "gap-10s", "error", c.text().encode(), line
    c = base.copy()
    for r in c.rows[ROW:]:
        r[c.col("t")] = repr(float(r[c.col("t")]) + 0.05)
    yield "gap-50ms", "error", c.text().encode(), line
    for label, scale in [("milliseconds", 1e3), ("microseconds", 1e6), ("nanoseconds", 1e9)]:
        c = base.copy()
        for r in c.rows:
            r[c.col("t")] = repr(float(r[c.col("t")]) * scale)
        yield f"time-in-{label}", "error", c.text().encode(), None
    c = base.copy()
    for r in c.rows:
        r[c.col("t")] = repr(float(r[c.col("t")]) / 1e3)  # 1 MHz
    yield "time-1MHz", "error", c.text().encode(), None
    c = base.copy()
    for r in c.rows:
        r[c.col("t")] = repr(float(r[c.col("t")]) + 1.7e9)
    yield "time-unix-epoch", "survive", c.text().encode(), None
    c = base.copy()
    for r in c.rows:
        r[c.col("t")] = repr(float(r[c.col("t")]) - 100.0)
    yield "time-negative", "survive", c.text().encode(), None
    c = base.copy(); c.set(ROW, "t", repr(float(c.rows[ROW - 1][c.col("t")]) + 1e-12))
    yield "time-step-1e-12", "any", c.text().encode(), None

    # The header.
    for label, edit in [
        ("missing-t", lambda c: c.drop_columns(lambda n: n == "t")),
        ("missing-gyro_z", lambda c: c.drop_columns(lambda n: n == "gyro_z")),
        ("missing-one-joint", lambda c: c.drop_columns(lambda n: n == "q_RL_1")),
        ("missing-gt_qz", lambda c: c.drop_columns(lambda n: n == "gt_qz")),
        ("unknown-column", lambda c: (c.header.append("banana"), [r.append("1") for r in c.rows])),
        ("duplicate-column", lambda c: (c.header.append("acc_x"),
                                        [r.append(r[c.col("acc_x")]) for r in c.rows])),
        ("header-upper-case", lambda c: c.header.__setitem__(0, "T")),
    ]:
        c = base.copy(); edit(c)
        yield f"header-{label}", "error", c.text().encode(), len(c.comments) + 1
    c = base.copy(); c.header[1] = " gyro_x "  # spaces around a name are not part of it
    yield "header-spaces", "survive", c.text().encode(), None
    yield "empty-file", "error", b"", None
    yield "header-only", "error", (",".join(base.header) + "\n").encode(), None
    yield "comments-only", "error", b"# robot: none\n# nothing else\n", None
    yield "binary-garbage", "error", bytes(range(256)) * 40, None
    yield "no-newline-at-all", "error", b"t" * 200_000, None
    yield "not-csv-json", "error", b'{"t": [0, 0.001]}\n', None
    c = base.copy(); c.rows = c.rows[:1]
    yield "one-row", "any", c.text().encode(), None
    c = base.copy(); c.rows = c.rows[:2]
    yield "two-rows", "any", c.text().encode(), None
    text = base.text()
    yield "truncated-last-row", "error", text[: len(text) - 40].encode(), None
    yield "trailing-blank-lines", "any", (text + "\n\n\n").encode(), None
    body = base.text().split("\n")
    body.insert(len(base.comments) + 2 + ROW, "")
    yield "blank-line-inside", "any", "\n".join(body).encode(), None

    # Line ends and encodings.
    yield "crlf", "survive", base.text("\r\n").encode(), None
    yield "cr-only", "survive", base.text("\r").encode(), None
    yield "utf8-bom", "survive", b"\xef\xbb\xbf" + base.text().encode(), None
    c = base.copy(); c.comments.append("# a comment with a \r carriage return")
    yield "comment-with-cr", "any", c.text().encode(), None
    yield "utf16", "error", base.text().encode("utf-16"), None

    # Finite but absurd values: the reader takes them, the estimators must not be corrupted.
    for column, value in [("gyro_x", "1e100"), ("gyro_y", "1e30"), ("acc_z", "1e10"),
                          ("acc_x", "1e200"), ("gyro_z", "-1e300"), ("q_FR_2", "1e10"),
                          ("dq_FL_1", "1e300"), ("force_FL", "-1e9"), ("tau_RR_0", "1e300")]:
        yield f"absurd-{column}={value}", "survive", spoil(column, value), None
    c = no_gt.copy(); c.set(0, "acc_x", "1e200")
    yield "absurd-first-row-acc-no-gt", "survive", c.text().encode(), None
    c = no_gt.copy()
    for r in c.rows:
        for a in ("acc_x", "acc_y", "acc_z"):
            r[c.col(a)] = "0"
    yield "free-fall-no-gt", "survive", c.text().encode(), None
    c = base.copy()
    for r in c.rows:
        for a in ("gyro_x", "gyro_y", "gyro_z"):
            r[c.col(a)] = "30"
    yield "spinning-30rad/s", "survive", c.text().encode(), None

    # Foot columns.
    c = feet_diag.copy(); c.set(ROW, "foot1_var_y", "-1e-6")
    yield "feet-negative-variance", "error", c.text().encode(), c.line_of_row(ROW)
    c = feet_diag.copy(); c.set(ROW, "foot1_var_y", "0")
    yield "feet-zero-variance", "error", c.text().encode(), c.line_of_row(ROW)
    c = feet_full.copy(); c.set(ROW, "foot2_cov_xy", "1")
    yield "feet-full-not-spd", "error", c.text().encode(), c.line_of_row(ROW)
    c = feet_diag.copy(); c.set(ROW, "foot3_px", "1e6")
    yield "feet-position-1e6", "survive", c.text().encode(), None
    c = feet_diag.copy()
    for r in c.rows:
        r[c.col("foot0_var_x")] = "1e30"
    yield "feet-variance-1e30", "survive", c.text().encode(), None
    c = feet_diag.copy()
    for r in c.rows:
        for a in ("x", "y", "z"):
            r[c.col(f"foot0_var_{a}")] = "1e-30"
    yield "feet-variance-1e-30", "survive", c.text().encode(), None
    yield "feet-diagonal", "survive", feet_diag.text().encode(), None
    yield "feet-full", "survive", feet_full.text().encode(), None
    c = feet_diag.copy()
    for k in (4, 5):  # a hexapod: two more feet, copies of the front pair, mirrored in x
        src = k - 4
        for suffix in ("px", "py", "pz", "var_x", "var_y", "var_z", "force", "contact"):
            name = f"foot{src}_{suffix}"
            if name not in c.header:
                continue
            c.header.append(f"foot{k}_{suffix}")
            for r in c.rows:
                v = r[c.col(name)]
                r.append(repr(-float(v)) if suffix == "px" else v)
    yield "feet-six-hexapod", "survive", c.text().encode(), None
    c = feet_diag.copy()
    c.header.extend(["foot6_px", "foot6_py", "foot6_pz", "foot6_var_x", "foot6_var_y",
                     "foot6_var_z"])
    for r in c.rows:
        r.extend(["0.3", "0.1", "-0.3", "1e-4", "1e-4", "1e-4"])
    yield "feet-seven", "error", c.text().encode(), None
    c = base.copy()
    for name in ("foot0_px", "foot0_py", "foot0_pz", "foot0_var_x", "foot0_var_y", "foot0_var_z"):
        c.header.append(name)
    for r in c.rows:
        r.extend(["0.2", "0.1", "-0.3", "1e-4", "1e-4", "1e-4"])
    yield "joints-and-feet", "error", c.text().encode(), None


def check_estimates(out_dir):
    """'' when every estimate file under out_dir is finite and physical, else what is not."""
    names = [n for n in os.listdir(out_dir) if n.startswith("estimate_") and n.endswith(".csv")]
    for name in names:
        with open(os.path.join(out_dir, name)) as f:
            rows = csv.reader(l for l in f if not l.startswith("#"))
            header = next(rows, None)
            if header is None:
                return f"{name} is empty"
            col = {n: i for i, n in enumerate(header)}
            for k, r in enumerate(rows):
                values = [float(x) for x in r]
                if not all(math.isfinite(v) for v in values):
                    return f"{name} row {k}: not finite"
                p = math.sqrt(sum(values[col[a]] ** 2 for a in ("px", "py", "pz")))
                v = math.sqrt(sum(values[col[a]] ** 2 for a in ("vx", "vy", "vz")))
                if p > 1e6 or v > 1e3:
                    return f"{name} row {k}: |p| = {p:.3g} m, |v| = {v:.3g} m/s"
    return ""


def run_case(legkit, work, name, expectation, contents, line):
    """(class, what was seen, seconds) of one case."""
    safe = "".join(ch if ch.isalnum() or ch in "-=." else "_" for ch in name)
    path = os.path.join(work, safe + ".csv")
    with open(path, "wb") as f:
        f.write(contents)
    out_dir = os.path.join(work, safe + ".out")
    started = time.monotonic()
    try:
        # Every estimate row is checked, not only the default 100 Hz ones.
        p = subprocess.run([legkit, "run", "--log", path, "--out", out_dir, "--no-plots",
                            "--estimate-rate", "all"], capture_output=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return "HANG", f"no answer in {TIMEOUT:.0f} s", TIMEOUT
    seconds = time.monotonic() - started
    err = p.stderr.decode(errors="replace")
    rc = p.returncode
    if rc < 0 or rc > 3:
        return "CRASH", f"exit {rc}: {err[-300:]}", seconds
    if len(err) > 2000:
        return "UNCLEAR", f"message of {len(err)} characters", seconds
    if expectation in ("error", "any") and rc == 2:
        if os.path.basename(path) not in err:
            return "UNCLEAR", f"exit 2 not naming the file: {err.strip()[:300]}", seconds
        if line is not None and f":{line}" not in err and f"line {line}" not in err:
            return "UNCLEAR", f"exit 2 not naming line {line}: {err.strip()[:300]}", seconds
        return "OK", f"refused: {err.strip()[:160]}", seconds
    if expectation == "error":
        cls = "SILENT" if rc in (0, 3) else "UNCLEAR"
        return cls, f"expected a refusal (exit 2), got exit {rc}: {err.strip()[:300]}", seconds
    if rc not in (0, 3):
        return "UNCLEAR", f"expected the run to go through, got exit {rc}: {err.strip()[:300]}", \
            seconds
    if not os.path.isdir(out_dir):
        return "SILENT", f"exit {rc} but no output folder", seconds
    problem = check_estimates(out_dir)
    return ("SILENT", problem, seconds) if problem else ("OK", f"ran, exit {rc}", seconds)


def main():
    args = parser(__doc__).parse_args()
    legkit = os.path.abspath(args.legkit)
    work = args.dir or tempfile.mkdtemp(prefix="legkit-bad-inputs-")
    os.makedirs(work, exist_ok=True)
    started = time.monotonic()
    try:
        def simulate(name, *extra):
            path = os.path.join(work, name)
            subprocess.run([legkit, "sim", "--duration", "1", "--out", path, *extra], check=True,
                           capture_output=True)
            return Log(path)

        base = simulate("base.csv")
        no_gt = simulate("base-no-gt.csv", "--no-ground-truth")
        feet_diag = feet_only(simulate("base-feet-diag.csv", "--foot-columns", "diagonal"))
        feet_full = feet_only(simulate("base-feet-full.csv", "--foot-columns", "full"))
        all_cases = list(cases(base, feet_diag, feet_full, no_gt))
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(lambda case: run_case(legkit, work, *case), all_cases))
        labels = [f"{name} ({expectation})" for name, expectation, _, _ in all_cases]
        return report("bad-input matrix", labels, results, started, args.verbose)
    finally:
        if not args.dir and not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
