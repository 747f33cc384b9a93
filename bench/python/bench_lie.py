"""What a call into legkit.lie costs from Python, and what the batched calls save.

Run by hand (not a test), from the source tree, with the package of a Release build:
    PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_lie.py
It prints the time of one SO3.Exp on one vector (timeit, best of 5) and its overhead over the
C++ work, then 10^6 rotation vectors through SO3.Exp_batch (the loop in C++, without the GIL)
against a Python loop of SO3.Exp(phi).matrix() over 10^4 of them, extrapolated to 10^6.
"""
import timeit

import numpy as np

from legkit.lie import SO3

N_BATCH = 10**6  # vectors through the batched call
N_LOOP = 10**4  # vectors through the Python loop (then extrapolated to N_BATCH)


def best(function, number, repeat=5):
    """Seconds per call: the best of `repeat` runs of `number` calls."""
    return min(timeit.repeat(function, number=number, repeat=repeat)) / number


def main():
    rng = np.random.default_rng(1)
    phi = rng.normal(size=3)
    phis = rng.normal(size=(N_BATCH, 3))

    one = best(lambda: SO3.Exp(phi), 100_000)
    one_matrix = best(lambda: SO3.Exp(phi).matrix(), 100_000)
    batch = best(lambda: SO3.Exp_batch(phis), 1, repeat=3)
    loop = best(lambda: [SO3.Exp(p).matrix() for p in phis[:N_LOOP]], 1, repeat=3)
    in_cpp = batch / N_BATCH  # one Exp and its 3x3 store, in the C++ loop

    print("SO3.Exp from Python, one (3,) vector (timeit, best of 5):")
    print(f"  SO3.Exp(phi)            {one * 1e9:8.0f} ns per call")
    print(f"  SO3.Exp(phi).matrix()   {one_matrix * 1e9:8.0f} ns per call")
    print(f"  of which the C++ Exp    {in_cpp * 1e9:8.0f} ns (from the batched call below)")
    print(f"  call overhead           {(one - in_cpp) * 1e9:8.0f} ns per call")
    print(f"Exp of {N_BATCH} vectors to (N, 3, 3) matrices:")
    rows = [("SO3.Exp_batch, the C++ loop", batch, in_cpp),
            (f"Python loop of {N_LOOP}, extrapolated", loop * N_BATCH / N_LOOP, loop / N_LOOP)]
    for label, total, each in rows:
        print(f"  {label:<36} {total:7.3f} s  ({each * 1e9:.0f} ns per vector)")
    print(f"  the batched call is {loop / N_LOOP / in_cpp:.0f}x faster")


if __name__ == "__main__":
    main()
