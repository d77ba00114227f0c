"""Per-call overhead of the Python package over the Rust job it runs.

`stickslip.hopf(scene)` from Python against the same library job timed in
Rust (`stickslip-bench --job hopf_job`: `jobs::hopf::run` on the default
scene), in interleaved rounds so that both see the same machine load. The
overhead is the difference of the medians: converting the arguments, the
JSON of the result and the result object.

    cargo build --release -p stickslip-bench
    pip install ./python            # into the environment that runs this
    python bench/python_overhead.py [--rounds 5] [--calls 2000]
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import time

import stickslip


def python_median(calls: int) -> float:
    """Median wall time of one `stickslip.hopf()` call, in seconds."""
    scene = stickslip.Scene.builtin("pmma")
    for _ in range(50):
        stickslip.hopf(scene)
    times = []
    for _ in range(calls):
        t0 = time.perf_counter()
        stickslip.hopf(scene)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def rust_median(bench: pathlib.Path) -> float:
    """Median time of the Rust job, in seconds, as stickslip-bench measures it."""
    out = subprocess.run(
        [str(bench), "--job", "hopf_job", "--json"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    (record,) = json.loads(out)
    return record["median_s"]


def main() -> None:
    root = pathlib.Path(__file__).resolve().parent.parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--calls", type=int, default=2000)
    parser.add_argument(
        "--bench", type=pathlib.Path, default=root / "target/release/stickslip-bench"
    )
    args = parser.parse_args()
    print(f"{'round':>5} {'Rust job [us]':>14} {'Python call [us]':>17} {'overhead [us]':>14}")
    overheads = []
    for r in range(args.rounds):
        rust = rust_median(args.bench)
        python = python_median(args.calls)
        overheads.append(python - rust)
        print(f"{r + 1:>5} {rust * 1e6:>14.1f} {python * 1e6:>17.1f} {(python - rust) * 1e6:>14.1f}")
    print(f"median overhead: {statistics.median(overheads) * 1e6:.1f} us per call")


if __name__ == "__main__":
    main()
