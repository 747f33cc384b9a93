#!/usr/bin/python3
"""The option matrix: every option with a value of every `legkit` command, given values that break.

    tools/bad-inputs/options.py --legkit build/legkit [--dir DIR] [--keep] [--jobs N] [--verbose]

Each option (and each positional argument) of `legkit run`, `tour`, `lie-accuracy`, `sim`, `cassie`,
`allan`, `config`, `robot`, `tune`, `eval`, `merge` and `legkit study consistency|convergence|
sweep|contact|slip|faults|fusion` is given, one at a time, each of the values
    0  -1  nan  inf  -inf  1e308  ''  a 10000-character string  (and 1e-308 where a number is read)
with the other arguments that keep an accepted run short (`--duration 1`, `--runs 1`,
`--no-plots`, a two-second log made once with `legkit sim --duration 2`, an output folder of its
own). Each case is run with a timeout (20 s) in a folder of its own and classified:
  OK       refused (exit 1 or 2) by a message that names the option (or, for a file or folder,
           the path given), or accepted because the value is valid for that option (the table
           below says which are) and the run ended cleanly (exit 0, or 3: it says what failed);
  SILENT   exit 0 or 3 with a value that is out of range: taken as it is, or replaced by a default;
  UNCLEAR  refused by a message that names neither the option nor the path;
  HANG     no answer within the timeout;
  CRASH    a signal, or an exit code above 3.
Prints one line per case that is not OK and the counts per class; exits 1 unless SILENT, UNCLEAR,
HANG and CRASH are all 0. `--verbose` prints the OK cases too.

Left out, to keep the whole matrix under a minute on two cores:
  - the valid values of options whose accepted run is long: `study faults --seed 0` (a 3 s physics
    trot and eleven fault runs), `study contact|slip --seed 0` (the probabilistic detector's
    training and the physics runs: 10 s each), every valid value of `study fusion` (a physics run
    and the smoother: 5 s at the least) and the valid names of `tune --out` (each a fit); their
    invalid values are all tried;
  - of the valid folder names (0, -1, nan, ...) of `run --out` and the studies' `--out`, all but
    -1 (the one a parser could take for an option): each is a run of seconds, and the names
    differ in nothing the kit reads; `sim`, `allan` and `lie-accuracy` try them all;
  - flags (they take no value) and `--help`/`--version`;
  - `legkit-estimate` (its own matrix) and the values inside files (tools/bad-inputs/matrix.py).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

from matrix_report import parser, report

TIMEOUT = 20.0
LONG = "x" * 10000
TEXT_VALUES = ["0", "-1", "nan", "inf", "-inf", "1e308", "", LONG]
NUMBER_VALUES = TEXT_VALUES + ["1e-308"]
# Valid names of files and folders among the values (an output may be called "nan").
NAMES = {"0", "-1", "nan", "inf", "-inf", "1e308", "1e-308"}


class Option:
    """One option of one command.

    command  the words after `legkit`, e.g. ("study", "slip");
    name     "--duration", or the name of a positional argument ("file") with positional=True;
    number   the option reads a number (1e-308 is tried too);
    valid    the tried values that are valid for it (exit 0 expected);
    base     the other arguments, as (option, value) pairs; ("", value) is a positional one; the
             tried option replaces a pair of its own name, and the names in `drop` are left out;
    path     the value names a file or folder: a refusal may name the path instead of the option;
    long     the valid values start a long run: they are left out;
    few      the valid values start a run of seconds: only one is tried ("-1" of the names, "0"
             of the numbers);
    second   the value after the tried one, for an option that takes two (--slip-direction).
    """

    def __init__(self, command, name, number=False, valid=(), base=(), drop=(), path=False,
                 long=False, few=False, positional=False, second=None):
        self.command, self.name, self.number = tuple(command), name, number
        self.valid, self.base, self.drop = set(valid), list(base), set(drop)
        self.path, self.long, self.positional, self.second = path, long, positional, second
        self.few = few

    def values(self):
        for value in NUMBER_VALUES if self.number else TEXT_VALUES:
            if value in self.valid and (self.long or (self.few and value not in ("-1", "0"))):
                continue
            yield value

    def argv(self, value, ctx):
        args = list(self.command)
        positionals = []
        for name, v in self.base:
            if name == self.name or name in self.drop:
                continue
            if v is None:  # a flag
                args.append(name)
            elif name == "":
                positionals.append(v.format(**ctx))
            else:
                args.append(f"{name}={v.format(**ctx)}")
        if self.positional:
            positionals.append(value)
        elif value == "":
            args += [self.name, ""]  # `--name=` is not an empty value everywhere
        else:
            args += [f"{self.name}={value}"]
        if self.second is not None:
            args.append(self.second)
        if positionals:
            args += ["--"] + positionals
        return args


def options():
    """Every option with a value of every command, with what is valid."""
    o = []
    out = ("--out", "{work}/out")
    run = [("--no-plots", None), out]  # flags are given as (name, None)

    def cmd(command, spec, base):
        for name, kw in spec:
            extra = kw.pop("base", [])  # replaces the command's pairs of the same names
            merged = [p for p in base if p[0] == "" or p[0] not in {e[0] for e in extra}]
            o.append(Option(command, name, base=merged + extra, **kw))

    # legkit run: on the short log, or a one-second simulated trot where the log is what is tried.
    on_log = [("--log", "{log}")]
    simulated = [("--duration", "1")]
    cmd(["run"], [
        ("--scenario", dict(base=simulated)),
        ("--duration", dict(number=True)),
        ("--seed", dict(number=True, valid={"0"}, base=simulated)),
        ("--log", dict(path=True)),
        ("--dataset", dict(base=simulated)),
        ("--max-gap", dict(number=True, base=on_log)),
        ("--out", dict(path=True, valid=NAMES, few=True, base=on_log)),
        ("--estimate-rate", dict(number=True, valid={"0"}, base=on_log)),
        ("--contact", dict(base=on_log)),
        ("--slip", dict(base=on_log)),
        ("--settle", dict(number=True, valid={"0", "1e-308"}, base=on_log)),
        ("--config", dict(path=True, base=on_log)),
    ], run)
    cmd(["tour"], [("--seed", dict(number=True, valid={"0"}))], [])
    cmd(["lie-accuracy"], [
        ("--csv", dict(path=True, valid=NAMES, base=[("--points", "10")])),
        ("--points", dict(number=True, base=[("--csv", "{work}/out.csv")])),
    ], [])

    # legkit sim: one simulated second; the slip options with a slipping foot.
    sim = [("--duration", "1"), ("--out", "{work}/log.csv")]
    slip = [("--slip-foot", "FR"), ("--slip-start", "0.2")]
    physics = [("--scenario", "physics-stand")]
    cmd(["sim"], [
        ("--scenario", {}),
        ("--duration", dict(number=True)),
        ("--rate", dict(number=True)),
        ("--seed", dict(number=True, valid={"0"})),
        ("--out", dict(path=True, valid=NAMES)),
        ("--foot-columns", {}),
        ("--slip-foot", {}),
        ("--slip-start", dict(number=True, valid={"0", "1e-308"}, base=slip)),
        ("--slip-duration", dict(number=True, base=slip)),
        ("--slip-speed", dict(number=True, valid={"0", "1e-308"}, base=slip)),
        ("--contact-offset", dict(number=True, valid={"0", "1e-308", "-1"})),
        ("--dropout", {}),
        ("--dropout-probability", dict(number=True, valid={"0", "1e-308"})),
        ("--friction", dict(number=True, base=physics)),
        ("--push", dict(number=True, valid={"0", "1e-308"},
                        base=[("--scenario", "physics-push"), ("--duration", "3.5")])),
        ("--closed-loop", dict(base=physics)),
    ], sim)
    # Two numbers: the tried one as X, 1 as Y (a direction (X, 1) is valid for any finite X
    # that a unit vector can be made of).
    o.append(Option(["sim"], "--slip-direction", number=True, valid={"0", "-1", "1e-308"},
                    base=sim + slip, second="1"))

    cmd(["cassie"], [("file", dict(path=True, positional=True))], [])
    allan = [("--simulate", "20"), ("--rate", "100"), ("--no-plots", None), out]
    cmd(["allan"], [
        ("file", dict(path=True, positional=True, drop={"--simulate", "--rate"})),
        ("--simulate", dict(number=True)),
        ("--rate", dict(number=True)),
        ("--seed", dict(number=True, valid={"0"})),
        ("--out", dict(path=True, valid=NAMES)),
        ("--ratio", dict(number=True)),
        ("--slope-tolerance", dict(number=True)),
    ], allan)
    cmd(["config"], [("--check", dict(path=True))], [])
    robot = [("", "{settings}")]
    cmd(["robot"], [
        ("settings", dict(path=True, positional=True, drop={""})),
        ("--angles", dict(number=True)),
        ("--log", dict(path=True)),
    ], robot)
    tune = [("", "{log}"), ("--out", "{work}/tuned.yaml")]
    cmd(["tune"], [
        ("log", dict(path=True, positional=True, drop={""})),
        ("--config", dict(path=True)),
        ("--estimator", {}),
        ("--fit-share", dict(number=True)),
        ("--out", dict(path=True, valid=NAMES, long=True)),
    ], tune)

    # legkit eval: a folder holding the short log; legkit merge: shard folders that are not.
    ev = [("", "{logs}"), ("--config", "{settings}"), out]
    cmd(["eval"], [
        ("dir", dict(path=True, positional=True, drop={""})),
        ("--config", dict(path=True)),
        ("--shard", {}),
        ("--out", dict(path=True, valid=NAMES, few=True)),
    ], ev)
    cmd(["merge"], [("shards", dict(path=True, positional=True))], [("", "{work}/merged")])

    # The studies: one run of one simulated second, no figure.
    mc = [("--runs", "1"), ("--duration", "1"), ("--no-plots", None), out]
    for study in ("consistency", "convergence", "sweep"):
        cmd(["study", study], [
            ("--runs", dict(number=True)),
            ("--duration", dict(number=True)),
            ("--seed", dict(number=True, valid={"0"})),
            ("--threads", dict(number=True, valid={"0"})),
            ("--out", dict(path=True, valid=NAMES, few=True)),
            ("--shard", {}),
        ], mc)
    physics_study = [("--duration", "1"), ("--no-plots", None), out]
    contact = physics_study + [("--scenarios", "physics-stand")]
    cmd(["study", "contact"], [
        ("--seed", dict(number=True, valid={"0"}, long=True)),
        ("--duration", dict(number=True)),
        ("--out", dict(path=True, valid=NAMES, few=True)),
        ("--scenarios", {}),
        ("--filter", {}),
        ("--shard", {}),
    ], contact)
    slip_study = physics_study + [("--scenarios", "physics-trot"), ("--filters", "eskf"),
                                  ("--contact", "truth")]
    cmd(["study", "slip"], [
        ("--seed", dict(number=True, valid={"0"}, long=True)),
        ("--duration", dict(number=True)),
        ("--out", dict(path=True, valid=NAMES, few=True)),
        ("--scenarios", {}),
        ("--contact", {}),
        ("--filters", {}),
        ("--shard", {}),
    ], slip_study)
    cmd(["study", "faults"], [
        ("--seed", dict(number=True, valid={"0"}, long=True)),
        ("--filter", {}),
        ("--shard", {}),
        # A shard's folder: without --shard any --out is refused (the whole study writes none).
        ("--out", dict(path=True, valid=NAMES, few=True, base=[("--shard", "1/7")])),
    ], [])
    fusion = [("--duration", "5"), ("--no-plots", None), out]
    cmd(["study", "fusion"], [
        ("--duration", dict(number=True)),
        ("--seed", dict(number=True, valid={"0"}, long=True)),
        ("--out", dict(path=True, valid=NAMES, long=True)),
        ("--shard", {}),  # refused past 1/1: one run, nothing to split
    ], fusion)
    return o


def names_it(err, option, value):
    """Whether the message names the option, or for a path the path given.

    An option's name counts only as a whole word (--duration is not in --slip-duration); a
    positional argument's ("file") only as CLI11 and the kit write it, followed by a colon."""
    name = re.escape(option.name) + (":" if option.positional else "")
    if re.search(r"(?<![\w-])" + name + r"(?![\w-])", err):
        return True
    if option.path and value:
        shown = value if len(value) < 100 else value[:100]
        return any(f"{shown}{end}" in err for end in (":", "'", '"', " ", ")")) or \
            any(f"{begin}{shown}" in err for begin in ("'", '"'))
    return False


def run_case(legkit, work, index, option, value, ctx):
    case = os.path.join(work, f"case{index}")
    os.makedirs(case)
    argv = [legkit] + option.argv(value, dict(ctx, work=case))
    started = time.monotonic()
    try:
        p = subprocess.run(argv, cwd=case, capture_output=True, timeout=TIMEOUT,
                           stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return "HANG", f"no answer in {TIMEOUT:.0f} s", time.monotonic() - started
    seconds = time.monotonic() - started
    shutil.rmtree(case, ignore_errors=True)
    err = p.stderr.decode(errors="replace").strip()
    last = err.splitlines()[-1] if err else ""
    rc = p.returncode
    if rc < 0 or rc > 3:
        return "CRASH", f"exit {rc}: {err[-300:]}", seconds
    if rc in (1, 2):
        if names_it(err, option, value):
            return "OK", f"refused (exit {rc}): {last[:160]}", seconds
        return "UNCLEAR", f"exit {rc}: {err[:300]}", seconds
    if value in option.valid:
        return "OK", f"valid, exit {rc}", seconds
    return "SILENT", f"exit {rc} with an invalid value: {last[:200]}", seconds


def show(value):
    return "''" if value == "" else ("<10000 x>" if value == LONG else value)


def main():
    ap = parser(__doc__)
    args = ap.parse_args()
    legkit = os.path.abspath(args.legkit)
    work = os.path.abspath(args.dir or tempfile.mkdtemp(prefix="legkit-options-"))
    os.makedirs(work, exist_ok=True)
    started = time.monotonic()
    try:
        log = os.path.join(work, "tiny.csv")
        subprocess.run([legkit, "sim", "--duration", "2", "--out", log], check=True,
                       capture_output=True)
        settings = os.path.join(work, "settings.yaml")
        with open(settings, "wb") as f:
            subprocess.run([legkit, "config", "--print"], check=True, stdout=f)
        logs = os.path.join(work, "logs")
        os.makedirs(logs, exist_ok=True)
        shutil.copy(log, logs)
        ctx = {"log": log, "settings": settings, "logs": logs}
        cases = [(option, value) for option in options() for value in option.values()]
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(
                lambda k: run_case(legkit, work, k, cases[k][0], cases[k][1], ctx),
                range(len(cases))))
        labels = [f"{' '.join(option.command)} {option.name} {show(value)}"
                  for option, value in cases]
        return report("option matrix", labels, results, started, args.verbose)
    finally:
        if not args.dir and not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
