"""One colour per estimator, by name, shared by every plot of the kit (run_plots.py, study_plots.py).

An estimator keeps its colour from figure to figure whichever others are drawn with it; a name the
kit does not know (a student's own estimator) gets one of the spare colours, always the same one.
"""
import zlib

TRUTH = "ground truth"

COLOURS = {
    TRUTH: "black",
    "imu-dead-reckoning": "tab:gray",
    "leg-odometry": "tab:orange",
    "linear-kf": "tab:purple",
    "eskf": "tab:blue",
    "invariant-ekf": "tab:green",
    "tsif": "tab:red",
}

SPARE = ("tab:brown", "tab:pink", "tab:olive", "tab:cyan")


def colour(name):
    """The colour of the estimator called name (or of the ground truth)."""
    if name in COLOURS:
        return COLOURS[name]
    return SPARE[zlib.crc32(name.encode()) % len(SPARE)]
