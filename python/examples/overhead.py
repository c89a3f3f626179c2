"""Times critspeed.linear() from Python, to set against the same work timed inside Rust by
`cargo bench --bench api` (api_linear_small_text, api_linear_file) and against the command line.

    python python/examples/overhead.py        # from the repository's root

Prints the best of 7 repeats per call (microseconds). The difference between the Python call and
the Rust bench on the same text is the binding's overhead: the argument handling, the GIL release,
the JSON object built as Python objects.
"""

import pathlib
import subprocess
import tempfile
import time
import timeit

import critspeed

ROOT = pathlib.Path(__file__).resolve().parents[2]
STUDY = ROOT / "studies" / "seed-hunting.toml"
SMALL = STUDY.read_text().replace(
    "[linear]", "[linear]\ngrid_points = 16\nspectrum_points = 2"
)


def best_us(f, number):
    return min(timeit.repeat(f, number=number, repeat=7)) / number * 1e6


def main():
    small = best_us(lambda: critspeed.linear(SMALL), 200)
    full = best_us(lambda: critspeed.linear(STUDY), 10)
    check = best_us(lambda: critspeed.check(SMALL), 200)
    binary = ROOT / "target" / "release" / "critspeed"
    with tempfile.TemporaryDirectory() as out:
        runs = []
        for _ in range(7):
            t = time.perf_counter()
            subprocess.run([binary, "linear", STUDY, "--json", "--out", out],
                           check=True, capture_output=True)
            runs.append(time.perf_counter() - t)
    print(f"critspeed.linear(small TOML text)        {small:10.1f} us")
    print(f"critspeed.check(small TOML text)         {check:10.1f} us")
    print(f"critspeed.linear(seed-hunting path)      {full:10.1f} us")
    print(f"critspeed linear --json (process, files) {min(runs) * 1e6:10.1f} us")


if __name__ == "__main__":
    main()
