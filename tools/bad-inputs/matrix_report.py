"""What the bad-input matrices (options.py, files.py) share: their common options and what they
print at the end."""
import argparse
import time

CLASSES = ("OK", "SILENT", "UNCLEAR", "HANG", "CRASH")


def report(matrix, labels, results, started, verbose):
    """Prints each case that is not OK (every case with verbose), the slowest case and the counts
    per class; returns the exit code: 0 when every case is OK, else 1.

    matrix   the matrix's name ("option matrix");
    labels   one label per case;
    results  one (class, what was seen, seconds) per case;
    started  time.monotonic() when the matrix started."""
    counts = {c: 0 for c in CLASSES}
    for label, (cls, what, seconds) in zip(labels, results):
        counts[cls] += 1
        if cls != "OK" or verbose:
            print(f"{cls:8s} {label}: {what} ({seconds:.1f} s)")
    slowest = max(range(len(results)), key=lambda k: results[k][2])
    print(f"slowest case: {labels[slowest]} ({results[slowest][2]:.1f} s)")
    print(f"{matrix}: {len(results)} cases in {time.monotonic() - started:.0f} s: " +
          ", ".join(f"{c} {n}" for c, n in counts.items()))
    return 0 if counts["OK"] == len(results) else 1


def parser(doc):
    """The options every matrix takes (--legkit, --dir, --keep, --jobs, --verbose); doc is the
    script's docstring."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--legkit", required=True, help="the legkit program")
    ap.add_argument("--dir", help="work folder (default: a temporary one, removed after)")
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    ap.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    ap.add_argument("--verbose", action="store_true", help="print the OK cases too")
    return ap
