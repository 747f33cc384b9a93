#!/usr/bin/python3
"""The file matrix: every file the kit reads or writes, given files and paths that break.

    tools/bad-inputs/files.py --legkit build/legkit [--estimate build/legkit-estimate]
                              [--dir DIR] [--keep] [--jobs N] [--verbose]

The surfaces, each given the broken inputs listed:
  - settings files, through `legkit run --log LOG --config F` and `legkit config --check F`: a
    missing file, a folder, an empty file, binary bytes, /dev/null, /dev/zero (refused by its type
    before any read: no hang, no memory exhausted), a FIFO (refused without opening it: open()
    would wait for a writer), 17 MiB (over the 16 MiB cap), YAML that does not parse, a second
    document after `---`, an unknown key, a string where a number goes, a NaN, inf, negative or zero
    noise density, a value out of its range; and the defaults (`legkit config --print`), accepted;
  - robot models, through the settings key robot.model (`legkit config --check`, a few through
    `legkit run --config`): a missing file, a folder, an empty file, binary bytes, text that is not
    XML, /dev/zero, a FIFO, a NaN in a joint's origin, seven feet, an unknown foot, base or joint, a
    foot that is the base, a foot named twice, a body that is its own ancestor (a loop), an external
    entity (XXE: MuJoCo expands none, the name would stay "&xxe;"), an XInclude (MuJoCo would skip
    it: the included links missing without a word); robot.base or robot.feet without
    robot.model; the Go2's shipped URDF, accepted, and with a mesh file that does not exist,
    accepted (the kit drops <visual> and <collision> unread);
  - `legkit allan FILE`: a missing file, a folder, an empty file, a header only, a wrong header,
    binary bytes, a FIFO, /dev/zero, a NaN, inf or 1e300 value, time not increasing, a gap, a
    moving record (a trot log); a resting record, accepted;
  - `legkit-estimate LOG` (when --estimate is given): a missing, folder, empty, FIFO log, a missing
    or bad settings file; `--out` at a device (/dev/null), a symbolic link, a folder, a path under a
    regular file: refused with the target unchanged; a valid run, accepted;
  - outputs: the user's own files in `legkit run --out`'s folder (keep.png, estimate_mine.csv,
    notes.txt) kept byte for byte; an output named like the run's (estimate_eskf.csv) that is a
    symbolic link or /dev/null left unreplaced; `--out /dev/null`, `--out FILE/sub`, `--out
    /proc/...` refused; `legkit sim --out`, `legkit lie-accuracy --csv` and `legkit-estimate --out`
    at /dev/null or a symbolic link refused with the device, the link and its target unchanged;
    standard output on /dev/full (`config --print`, `config --check`, `run --log`, `allan`,
    `legkit-estimate`): a non-zero exit; `legkit run` sent SIGTERM mid-run, then run again into the
    same folder: no `.tmp` file left.
Each case is run with a timeout (20 s) in a folder of its own and classified:
  OK       refused (exit 1 or 2) by a message naming the file (its path, or its name where the kit
           names a file it found through another, a model through its settings) and, where it
           applies, the key; or accepted (exit 0) when the input is valid; and, where the case
           checks it, every user file, device and link as it was;
  SILENT   exit 0 or 3 on a bad input, or a user's file, a device or a link replaced or changed;
  UNCLEAR  refused by a message that names neither the file nor the key;
  HANG     no answer within the timeout;
  CRASH    a signal, or an exit code above 3.
Prints one line per case that is not OK and the counts per class; exits 1 unless SILENT, UNCLEAR,
HANG and CRASH are all 0. `--verbose` prints the OK cases too. Runs as root in CI, so a read-only
folder is made as a path under a regular file (or in /proc), never with chmod.

Left out:
  - pose files (estimation/fusion/pose_log.hpp): no command reads one (`legkit study fusion`
    simulates its poses); the reader's refusals are tests/io/pose_log_checks_test.cpp's and the
    fuzzer's (fuzz/pose_log_fuzz.cpp);
  - the values inside logs (tools/bad-inputs/matrix.py) and the options' values
    (tools/bad-inputs/options.py);
  - a disk that fills while a file is written (tests/tools/output_test.cpp, against /dev/full);
  - `legkit tune --out` and the studies' `--out`: each accepted run is a fit or a study of
    seconds; they write through the same helpers as `legkit run` (tools/legkit/output.hpp).
"""
import os
import random
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

from matrix_report import parser, report

TIMEOUT = 20.0
GO2 = "data/robots/unitree/go2_description.urdf"
GO2_FEET = ["FL_foot", "FR_foot", "RL_foot", "RR_foot"]
GO2_JOINTS = [f"{leg}_{j}_joint" for leg in ("FL", "FR", "RL", "RR")
              for j in ("hip", "thigh", "calf")]


class Case:
    """One file given to one command.

    label    what is tried, for the report;
    argv     function(ctx) -> the arguments ("{legkit}" and "{estimate}" are the programs);
    setup    function(ctx) run in the case's folder before it, making its files;
    valid    the input is valid: exit 0 expected;
    names    for a refusal: groups of strings; the message must hold one of each group (the
             path, and the key where one applies); formatted with ctx;
    check    function(ctx) -> "" or what was destroyed (run after the command, whatever its exit);
    stdout   a path the command's standard output goes to (/dev/full), else captured;
    kind     "term": the command is sent SIGTERM once a .tmp file appears, then `then` is run.
    """

    def __init__(self, label, argv, setup=None, valid=False, names=(), check=None, stdout=None,
                 kind="", then=None):
        self.label, self.argv, self.setup, self.valid = label, argv, setup, valid
        self.names, self.check, self.stdout = [tuple(g) for g in names], check, stdout
        self.kind, self.then = kind, then


# --- making files ---------------------------------------------------------------------------

def write(path, data):
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def binary():
    return bytes(random.Random(7).randrange(256) for _ in range(4096))


def settings_text(ctx, replace=None, append=""):
    """The default settings, with `replace` ({line start: new line}) and `append`."""
    lines = ctx["defaults"].splitlines()
    for start, new in (replace or {}).items():
        hits = [k for k, l in enumerate(lines) if l.startswith(start)]
        assert len(hits) == 1, start
        lines[hits[0]] = new
    return "\n".join(lines) + "\n" + append


def robot_yaml(model, base="base", feet=GO2_FEET, joints=GO2_JOINTS, with_model=True):
    text = "robot:\n"
    if with_model:
        text += f"  model: {model}\n"
    if base is not None:
        text += f"  base: {base}\n"
    if feet is not None:
        text += f"  feet: [{', '.join(feet)}]\n"
    if joints is not None:
        text += f"  joints: [{', '.join(joints)}]\n"
    return text


def go2(ctx):
    with open(os.path.join(ctx["source"], GO2)) as f:
        return f.read()


def urdf_edit(ctx, old, new, count=1):
    text = go2(ctx)
    assert old in text, old
    return text.replace(old, new, count)


def mkfifo(path):
    os.mkfifo(path)


def state(path):
    """What a path is (type, link target, content), to check that it is unchanged."""
    try:
        s = os.lstat(path)
    except FileNotFoundError:
        return ("missing",)
    if stat.S_ISLNK(s.st_mode):
        return ("link", os.readlink(path))
    if stat.S_ISCHR(s.st_mode):
        return ("char", s.st_rdev)
    if stat.S_ISREG(s.st_mode):
        with open(path, "rb") as f:
            return ("file", f.read())
    return ("other", stat.S_IFMT(s.st_mode))


def unchanged(paths):
    """A setup remembering the state of paths, and a check comparing them after the run."""
    before = {}

    def remember(ctx):
        for p in paths:
            full = p.format(**ctx)
            before[full] = state(full)

    def check(ctx):
        changed = [p for p, s in before.items() if state(p) != s]
        return ("changed: " + ", ".join(changed)) if changed else ""
    return remember, check


def chain(*steps):
    def run(ctx):
        for s in steps:
            if s:
                s(ctx)
    return run


# --- the cases ------------------------------------------------------------------------------

def settings_cases():
    """Settings files, each through `legkit run --config` and `legkit config --check`."""
    bad = [
        # label, setup(ctx) making {case}/s.yaml (or None: the path itself), path, key names
        ("missing", None, "{case}/missing.yaml", ()),
        ("folder", lambda c: os.mkdir(c["case"] + "/s.yaml"), "{case}/s.yaml", ()),
        ("empty", lambda c: write(c["case"] + "/s.yaml", ""), "{case}/s.yaml", ()),
        ("comments only", lambda c: write(c["case"] + "/s.yaml", "# nothing\n\n"),
         "{case}/s.yaml", ()),
        ("binary", lambda c: write(c["case"] + "/s.yaml", binary()), "{case}/s.yaml", ()),
        ("/dev/null", None, "/dev/null", ()),
        ("/dev/zero", None, "/dev/zero", ()),
        ("FIFO", lambda c: mkfifo(c["case"] + "/s.yaml"), "{case}/s.yaml", ()),
        ("17 MiB", lambda c: write(c["case"] + "/s.yaml", ("#" * 1023 + "\n") * (17 << 10)),
         "{case}/s.yaml", ()),
        ("YAML that does not parse",
         lambda c: write(c["case"] + "/s.yaml", "imu: [0.1, 0.2\nfeet: {\n"), "{case}/s.yaml", ()),
        ("second document",
         lambda c: write(c["case"] + "/s.yaml", settings_text(c, append="---\nimu: {}\n")),
         "{case}/s.yaml", ()),
        ("unknown key",
         lambda c: write(c["case"] + "/s.yaml", settings_text(c, append="imu_typo: 1\n")),
         "{case}/s.yaml", ("imu_typo",)),
        ("text for a number",
         lambda c: write(c["case"] + "/s.yaml", settings_text(
             c, {"  gyro_noise_density:": "  gyro_noise_density: fast"})),
         "{case}/s.yaml", ("gyro_noise_density",)),
    ]
    for value in ("nan", ".nan", ".inf", "-0.004", "0"):
        bad.append((f"gyro_noise_density {value}",
                    lambda c, v=value: write(c["case"] + "/s.yaml", settings_text(
                        c, {"  gyro_noise_density:": f"  gyro_noise_density: {v}"})),
                    "{case}/s.yaml", ("gyro_noise_density",)))
    bad.append(("accel_noise_density 1e300",
                lambda c: write(c["case"] + "/s.yaml", settings_text(
                    c, {"  accel_noise_density:": "  accel_noise_density: 1e300"})),
                "{case}/s.yaml", ("accel_noise_density",)))
    bad.append(("initialisation.duration 1000",
                lambda c: write(c["case"] + "/s.yaml", settings_text(
                    c, {"  duration:": "  duration: 1000"})),
                "{case}/s.yaml", ("duration",)))
    cases = []
    for label, setup, path, keys in bad:
        names = [(path,)] + ([keys] if keys else [])
        cases.append(Case("run --config: " + label,
                          lambda c, p=path: ["{legkit}", "run", "--log", "{log}", "--no-plots",
                                             "--out", "{case}/out", "--config", p],
                          setup=setup, names=names))
        cases.append(Case("config --check: " + label,
                          lambda c, p=path: ["{legkit}", "config", "--check", p],
                          setup=setup, names=names))
    defaults = lambda c: write(c["case"] + "/s.yaml", c["defaults"])  # noqa: E731
    cases.append(Case("run --config: the defaults",
                      lambda c: ["{legkit}", "run", "--log", "{log}", "--no-plots", "--out",
                                 "{case}/out", "--config", "{case}/s.yaml"],
                      setup=defaults, valid=True))
    cases.append(Case("config --check: the defaults",
                      lambda c: ["{legkit}", "config", "--check", "{case}/s.yaml"],
                      setup=defaults, valid=True))
    return cases


def robot_cases():
    """Robot models through robot.model; s.yaml names model.urdf beside it."""
    def with_model(make_model=None, model="model.urdf", **kw):
        def setup(c):
            if make_model:
                make_model(c, c["case"] + "/" + model)
            write(c["case"] + "/s.yaml", robot_yaml(model, **kw))
        return setup

    def text(f):
        return lambda c, p: write(p, f(c))

    loop = ('<joint name="loop_joint" type="revolute"><parent link="FL_calf"/>'
            '<child link="base"/><axis xyz="0 1 0"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n</robot>')
    xxe = ('<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>\n')
    xinclude = ('<xi:include xmlns:xi="http://www.w3.org/2001/XInclude" href="/etc/passwd" '
                'parse="text"/>\n</robot>')
    mesh = ('<link name="base">\n    <visual><geometry><mesh filename="meshes/not_there.dae"/>'
            '</geometry></visual>')
    model_names = [("model.urdf",), ("robot.model",)]
    bad = [
        ("missing model", with_model(), model_names),
        ("model a folder", with_model(lambda c, p: os.mkdir(p)), model_names),
        ("empty model", with_model(text(lambda c: "")), model_names),
        ("binary model", with_model(text(lambda c: binary())), model_names),
        ("model not XML", with_model(text(lambda c: "robot: go2\nlegs: 4\n")), model_names),
        ("model /dev/zero", with_model(model="/dev/zero"), [("/dev/zero",), ("robot.model",)]),
        ("model a FIFO", with_model(lambda c, p: mkfifo(p)), model_names),
        ("NaN in an origin", with_model(text(lambda c: urdf_edit(
            c, '<origin xyz="0.1934 -0.0465 0" rpy="0 0 0" />',
            '<origin xyz="nan -0.0465 0" rpy="0 0 0" />'))), model_names),
        ("seven feet", with_model(text(go2), feet=GO2_FEET + ["FL_calf", "FR_calf", "RL_calf"]),
         model_names),
        ("unknown foot", with_model(text(go2), feet=["FL_foot", "FR_foot", "RL_foot", "XX_foot"]),
         model_names + [("XX_foot",)]),
        ("unknown base", with_model(text(go2), base="torso"), model_names + [("torso",)]),
        ("foot is the base", with_model(text(go2), feet=["base", "FR_foot", "RL_foot", "RR_foot"]),
         model_names),
        ("foot named twice", with_model(text(go2), feet=["FL_foot", "FL_foot", "RL_foot",
                                                         "RR_foot"]),
         [("s.yaml",), ("robot.feet",)]),
        ("unknown joint", with_model(text(go2), joints=GO2_JOINTS[:-1] + ["knee_joint"]),
         model_names + [("knee_joint",)]),
        ("a loop", with_model(text(lambda c: urdf_edit(c, "</robot>", loop))), model_names),
        ("external entity", with_model(text(lambda c: xxe + go2(c).split("\n", 1)[1].replace(
            '<robot name="go2_description">', '<robot name="&xxe;">'))), model_names),
        ("XInclude", with_model(text(lambda c: urdf_edit(c, "</robot>", xinclude))),
         model_names),
        ("base without model", with_model(with_model=False, feet=None, joints=None),
         [("s.yaml",), ("robot.base", "robot.model", "model")]),
        ("feet without model", with_model(with_model=False, base=None, joints=None),
         [("s.yaml",), ("robot.feet", "robot.model", "model")]),
    ]
    cases = []
    for label, setup, names in bad:
        cases.append(Case("config --check: " + label,
                          lambda c: ["{legkit}", "config", "--check", "{case}/s.yaml"],
                          setup=setup, names=names))
    # Through `legkit run` on the iCub's log (generic joint columns), and on the built-in
    # simulation (the Go2's joints, refused for any robot.model, but the model's own fault first).
    for label, setup, names in [bad[0], bad[7], bad[9], bad[17]]:
        cases.append(Case("run --config: " + label,
                          lambda c: ["{legkit}", "run", "--log", "{icub}", "--no-plots", "--out",
                                     "{case}/out", "--config", "{case}/s.yaml"],
                          setup=setup, names=names))
    for label, setup, names in [bad[0], bad[2], bad[3], bad[7]]:
        cases.append(Case("run --config, simulated: " + label,
                          lambda c: ["{legkit}", "run", "--duration", "1", "--no-plots", "--out",
                                     "{case}/out", "--config", "{case}/s.yaml"],
                          setup=setup, names=names))
    cases.append(Case("config --check: the Go2's URDF",
                      lambda c: ["{legkit}", "config", "--check", "{case}/s.yaml"],
                      setup=with_model(text(go2)), valid=True))
    # The kit reads the kinematics only: <visual> and <collision> are dropped unread, so a mesh
    # that is not there is valid (the shipped Unitree URDFs come without their meshes).
    cases.append(Case("config --check: a mesh not there",
                      lambda c: ["{legkit}", "config", "--check", "{case}/s.yaml"],
                      setup=with_model(text(lambda c: urdf_edit(c, '<link name="base">', mesh))),
                      valid=True))
    return cases


def resting(rows=3000, rate=100.0, edit=None):
    """A plain IMU recording at rest (t,gx,gy,gz,ax,ay,az); edit(k, fields) may change a row."""
    rng = random.Random(3)
    lines = ["t,gx,gy,gz,ax,ay,az"]
    for k in range(rows):
        fields = [f"{k / rate:.6f}"] + [f"{rng.gauss(0, 0.002):.6g}" for _ in range(3)] + \
            [f"{rng.gauss(0, 0.02):.6g}", f"{rng.gauss(0, 0.02):.6g}",
             f"{9.81 + rng.gauss(0, 0.02):.6g}"]
        if edit:
            fields = edit(k, fields)
        if fields is not None:
            lines.append(",".join(fields))
    return "\n".join(lines) + "\n"


def allan_cases():
    def setting(k, col, value):
        def edit(row, fields):
            if row == k:
                fields[col] = value
            return fields
        return edit

    def at(make):
        return lambda c: make(c["case"] + "/imu.csv")

    path = [("{case}/imu.csv",)]
    bad = [
        ("missing", None, path),
        ("folder", at(os.mkdir), path),
        ("empty", at(lambda p: write(p, "")), path),
        ("header only", at(lambda p: write(p, "t,gx,gy,gz,ax,ay,az\n")), path),
        ("wrong header", at(lambda p: write(p, resting().replace("gx,", "wx,", 1))), path),
        ("binary", at(lambda p: write(p, binary())), path),
        ("FIFO", at(mkfifo), path),
        ("NaN", at(lambda p: write(p, resting(edit=setting(500, 2, "nan")))), path),
        ("inf", at(lambda p: write(p, resting(edit=setting(500, 4, "inf")))), path),
        ("1e300", at(lambda p: write(p, resting(edit=setting(500, 5, "1e300")))), path),
        ("time not increasing",
         at(lambda p: write(p, resting(edit=setting(500, 0, "4.0")))), path),
        ("a gap", at(lambda p: write(p, resting(edit=lambda k, f: None if 500 <= k < 600 else f))),
         path),
        ("a moving record (a trot)", lambda c: shutil.copy(c["log"], c["case"] + "/imu.csv"), path),
    ]
    cases = [Case("allan: " + label,
                  lambda c: ["{legkit}", "allan", "--no-plots", "--out", "{case}/out", "--",
                             "{case}/imu.csv"], setup=setup, names=names)
             for label, setup, names in bad]
    cases.append(Case("allan: /dev/zero",
                      lambda c: ["{legkit}", "allan", "--no-plots", "--out", "{case}/out", "--",
                                 "/dev/zero"], names=[("/dev/zero",)]))
    cases.append(Case("allan: a resting record",
                      lambda c: ["{legkit}", "allan", "--no-plots", "--out", "{case}/out", "--",
                                 "{case}/imu.csv"],
                      setup=at(lambda p: write(p, resting())), valid=True))
    return cases


def estimate_cases():
    log = [("{case}/log.csv",)]
    bad = [
        ("log missing", None, log),
        ("log a folder", lambda c: os.mkdir(c["case"] + "/log.csv"), log),
        ("log empty", lambda c: write(c["case"] + "/log.csv", ""), log),
        ("log a FIFO", lambda c: mkfifo(c["case"] + "/log.csv"), log),
        ("log binary", lambda c: write(c["case"] + "/log.csv", binary()), log),
    ]
    cases = [Case("legkit-estimate: " + label,
                  lambda c: ["{estimate}", "{case}/log.csv"], setup=setup, names=names)
             for label, setup, names in bad]
    settings = [
        ("settings missing", None, [("{case}/s.yaml",)]),
        ("settings a FIFO", lambda c: mkfifo(c["case"] + "/s.yaml"), [("{case}/s.yaml",)]),
        ("settings unknown key",
         lambda c: write(c["case"] + "/s.yaml", settings_text(c, append="imu_typo: 1\n")),
         [("{case}/s.yaml",), ("imu_typo",)]),
        ("settings NaN density",
         lambda c: write(c["case"] + "/s.yaml", settings_text(
             c, {"  gyro_noise_density:": "  gyro_noise_density: .nan"})),
         [("{case}/s.yaml",), ("gyro_noise_density",)]),
        ("settings robot.model missing",
         lambda c: write(c["case"] + "/s.yaml", robot_yaml(
             "model.urdf", base="root_link", feet=["l_sole", "r_sole"], joints=None)),
         [("model.urdf",), ("robot.model",)]),
    ]
    cases += [Case("legkit-estimate: " + label,
                   lambda c: ["{estimate}", "{icub}", "--config", "{case}/s.yaml"],
                   setup=setup, names=names) for label, setup, names in settings]
    cases.append(Case("legkit-estimate: a valid run, --out states.csv",
                      lambda c: ["{estimate}", "{log}", "--out", "{case}/states.csv"], valid=True,
                      check=lambda c: "" if os.path.isfile(c["case"] + "/states.csv")
                      else "no states.csv written"))
    return cases


def output_cases(have_estimate):
    cases = []
    run = ["{legkit}", "run", "--log", "{log}", "--no-plots"]

    # The user's own files in the output folder, before a first run and before a second.
    mine = {"keep.png": b"\x89PNG my figure", "estimate_mine.csv": b"t,x\n0,1\n",
            "notes.txt": b"my notes\n"}

    def users(c):
        os.makedirs(c["case"] + "/out")
        for name, data in mine.items():
            write(c["case"] + "/out/" + name, data)

    def users_kept(c):
        lost = [n for n, d in mine.items() if state(c["case"] + "/out/" + n) != ("file", d)]
        if not os.path.isfile(c["case"] + "/out/summary.json"):
            lost.append("(summary.json not written)")
        return ("user files lost or changed: " + ", ".join(lost)) if lost else ""
    cases.append(Case("run --out: the user's files kept", lambda c: run + ["--out", "{case}/out"],
                      setup=users, valid=True, check=users_kept))
    cases.append(Case("run --out: the user's files kept over a second run",
                      lambda c: ["sh", "-c", '"$@" && "$@"', "sh"] + run + ["--out", "{case}/out"],
                      setup=users, valid=True, check=users_kept))

    # Outputs named like the run's: a link to the user's file, a link to /dev/null.
    for target, label in (("{case}/precious.csv", "a link to a user file"),
                          ("/dev/null", "a link to /dev/null")):
        def setup(c, target=target):
            os.makedirs(c["case"] + "/out")
            write(c["case"] + "/precious.csv", "mine\n")
            os.symlink(target.format(**c), c["case"] + "/out/estimate_eskf.csv")
        remember, check = unchanged(["{case}/out/estimate_eskf.csv", "{case}/precious.csv",
                                     "/dev/null"])
        cases.append(Case("run --out: estimate_eskf.csv " + label,
                          lambda c: run + ["--out", "{case}/out"],
                          setup=chain(setup, remember), check=check,
                          names=[("estimate_eskf.csv",)]))

    remember, check = unchanged(["/dev/null"])
    cases.append(Case("run --out /dev/null", lambda c: run + ["--out", "/dev/null"],
                      setup=remember, check=check, names=[("/dev/null",)]))
    cases.append(Case("run --out under a regular file",
                      lambda c: run + ["--out", "{case}/somefile/sub"],
                      setup=lambda c: write(c["case"] + "/somefile", "x\n"),
                      names=[("{case}/somefile/sub",)]))
    cases.append(Case("run --out in /proc", lambda c: run + ["--out", "/proc/legkit-out"],
                      names=[("/proc/legkit-out",)]))

    # Single-file outputs at a device or a link.
    singles = [("sim --out", ["{legkit}", "sim", "--duration", "0.2", "--out"]),
               ("lie-accuracy --csv", ["{legkit}", "lie-accuracy", "--points", "10", "--csv"])]
    if have_estimate:
        singles.append(("legkit-estimate --out", ["{estimate}", "{log}", "--out"]))
    for label, argv in singles:
        remember, check = unchanged(["/dev/null"])
        cases.append(Case(label + " /dev/null", lambda c, a=argv: a + ["/dev/null"],
                          setup=remember, check=check, names=[("/dev/null",)]))

        def link(c):
            write(c["case"] + "/precious.csv", "mine\n")
            os.symlink(c["case"] + "/precious.csv", c["case"] + "/link.csv")
        remember, check = unchanged(["{case}/link.csv", "{case}/precious.csv"])
        cases.append(Case(label + " a symbolic link", lambda c, a=argv: a + ["{case}/link.csv"],
                          setup=chain(link, remember), check=check,
                          names=[("{case}/link.csv",)]))
        cases.append(Case(label + " a folder", lambda c, a=argv: a + ["{case}/dir"],
                          setup=lambda c: os.mkdir(c["case"] + "/dir"),
                          names=[("{case}/dir",)]))
        cases.append(Case(label + " under a regular file",
                          lambda c, a=argv: a + ["{case}/somefile/x.csv"],
                          setup=lambda c: write(c["case"] + "/somefile", "x\n"),
                          names=[("{case}/somefile/x.csv",)]))

    # Standard output on a full disk.
    full = [("config --print", ["{legkit}", "config", "--print"]),
            ("config --check", ["{legkit}", "config", "--check", "{source}/config/legkit.yaml"]),
            ("run --log", run + ["--out", "{case}/out"]),
            ("allan --simulate", ["{legkit}", "allan", "--simulate", "20", "--rate", "100",
                                  "--no-plots", "--out", "{case}/out"])]
    if have_estimate:
        full.append(("legkit-estimate", ["{estimate}", "{log}"]))
    for label, argv in full:
        cases.append(Case(label + " > /dev/full", lambda c, a=argv: a, stdout="/dev/full",
                          names=[("standard output", "stdout")]))

    # SIGTERM mid-run, then a run into the same folder: no .tmp left.
    cases.append(Case("run SIGTERM mid-run, then again: no .tmp",
                      lambda c: ["{legkit}", "run", "--scenario", "trot", "--duration", "60",
                                 "--no-plots", "--out", "{case}/out"],
                      kind="term", valid=True,
                      then=lambda c: run + ["--out", "{case}/out"]))
    return cases


# --- running and judging --------------------------------------------------------------------

def fmt(items, ctx):
    return [i.format(**ctx) for i in items]


def names_it(err, case, ctx):
    return all(any(n.format(**ctx) in err for n in group) for group in case.names)


def run_case(work, index, case, ctx):
    folder = os.path.join(work, f"case{index}")
    os.makedirs(folder)
    ctx = dict(ctx, case=folder)
    if case.setup:
        case.setup(ctx)
    argv = fmt(case.argv(ctx), ctx)
    started = time.monotonic()
    out = open(case.stdout, "wb") if case.stdout else subprocess.PIPE
    try:
        if case.kind == "term":
            p = subprocess.Popen(argv, cwd=folder, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
            # SIGTERM while a .tmp is being written (or after half the timeout without one).
            deadline = time.monotonic() + TIMEOUT / 2
            while p.poll() is None and time.monotonic() < deadline and not any(
                    f.endswith(".tmp") for _, _, fs in os.walk(folder) for f in fs):
                time.sleep(0.002)
            p.send_signal(signal.SIGTERM)
            p.wait(timeout=TIMEOUT)
            argv = fmt(case.then(ctx), ctx)
        p = subprocess.run(argv, cwd=folder, stdout=out, stderr=subprocess.PIPE, timeout=TIMEOUT,
                           stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return "HANG", f"no answer in {TIMEOUT:.0f} s", time.monotonic() - started
    finally:
        if case.stdout:
            out.close()
    seconds = time.monotonic() - started
    err = p.stderr.decode(errors="replace").strip()
    last = err.splitlines()[-1] if err else ""
    rc = p.returncode
    problem = case.check(ctx) if case.check else ""
    if case.kind == "term":
        left = [os.path.join(d, f) for d, _, fs in os.walk(folder) for f in fs
                if f.endswith(".tmp")]
        if left:
            problem = "left: " + ", ".join(os.path.relpath(f, folder) for f in left)
    shutil.rmtree(folder, ignore_errors=True)
    if rc < 0 or rc > 3:
        return "CRASH", f"exit {rc}: {err[-300:]}", seconds
    if problem:
        return "SILENT", f"exit {rc}, {problem}: {last[:160]}", seconds
    if case.valid:
        if rc == 0:
            return "OK", "valid, exit 0", seconds
        return "SILENT" if rc == 3 else "UNCLEAR", f"valid input, exit {rc}: {err[:300]}", seconds
    if rc in (1, 2):
        if names_it(err, case, ctx):
            return "OK", f"refused (exit {rc}): {last[:160]}", seconds
        return "UNCLEAR", f"exit {rc}: {err[:300]}", seconds
    return "SILENT", f"exit {rc} on a bad input: {last[:200]}", seconds


def main():
    ap = parser(__doc__)
    ap.add_argument("--estimate", help="the legkit-estimate program (its cases are left out "
                    "without it)")
    args = ap.parse_args()
    legkit = os.path.abspath(args.legkit)
    source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    work = os.path.abspath(args.dir or tempfile.mkdtemp(prefix="legkit-files-"))
    os.makedirs(work, exist_ok=True)
    started = time.monotonic()
    try:
        log = os.path.join(work, "tiny.csv")
        subprocess.run([legkit, "sim", "--duration", "2", "--out", log], check=True,
                       capture_output=True)
        defaults = subprocess.run([legkit, "config", "--print"], check=True,
                                  capture_output=True).stdout.decode()
        ctx = {"legkit": legkit, "estimate": os.path.abspath(args.estimate or "-"), "log": log,
               "defaults": defaults, "source": source,
               "icub": os.path.join(source, "data/icub-walking/walking.csv")}
        cases = settings_cases() + robot_cases() + allan_cases() + \
            (estimate_cases() if args.estimate else []) + output_cases(bool(args.estimate))
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(lambda k: run_case(work, k, cases[k], ctx),
                                    range(len(cases))))
        return report("file matrix", [case.label for case in cases], results, started,
                      args.verbose)
    finally:
        if not args.dir and not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
