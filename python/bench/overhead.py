"""The cost of driving a run from Python: a Simulation stepped `--steps` at a time against
`dem2d run --max-steps` on the same pile, interleaved, medians of `--reps` pairs.

    python python/bench/overhead.py target/bench-piles/settle_disks_10k_settled.json

(the settled piles of `dem2d-lab bench`, cached in target/bench-piles). Three timings of the same
steps from the same state, each the median over the repetitions:
- cli: `dem2d run PILE --max-steps N --threads T --quiet`, the summary's `wall_seconds` (its step
  loop, with its writers: trajectory, increments, walls);
- python: `Simulation(pile, threads=T).run(N)` without files, the call's wall time (the GIL
  released and taken back, the worker thread, the pool);
- python+files: the same with `out=` (the writers of `dem2d run`, and a frame at the end of the call).
The overhead is python / cli − 1. Speed is noisy on a shared machine: interleaving puts each pair
under the same load. And within each Python call, free of that noise: the call's wall time against
its own step loop's (`Simulation.wall_seconds`, the run driver's clock, as the summary's
`wall_seconds`), the cost of the Python layer itself.
"""

import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import dem2d


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("pile")
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--reps", type=int, default=7)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--dem2d", default="target/release/dem2d")
    a = p.parse_args()
    case = dem2d.Case.load(a.pile)
    times = {"cli": [], "python": [], "python+files": []}
    within = {"python": [], "python+files": []}
    with tempfile.TemporaryDirectory() as tmp:
        for rep in range(a.reps):
            out = Path(tmp) / "cli"
            subprocess.run(
                [a.dem2d, "run", a.pile, "--out", out, "--max-steps", str(a.steps), "--threads",
                 str(a.threads), "--quiet", "--overwrite"],
                check=True, capture_output=True,
            )
            times["cli"].append(json.loads((out / "summary.json").read_text())["wall_seconds"])
            for name, files in (("python", None), ("python+files", Path(tmp) / "py")):
                sim = dem2d.Simulation(case, threads=a.threads, out=files, overwrite=True)
                start = time.perf_counter()
                sim.run(a.steps)
                times[name].append(time.perf_counter() - start)
                within[name].append(times[name][-1] / sim.wall_seconds - 1)
                del sim
            print(f"rep {rep + 1}: " + ", ".join(f"{k} {v[-1]:.4f} s" for k, v in times.items()), flush=True)
    med = {k: statistics.median(v) for k, v in times.items()}
    n = case.n_bodies
    print(f"{n} bodies, {a.steps} steps a call, {a.threads} thread(s), median of {a.reps}:")
    for k, v in med.items():
        over = "" if k == "cli" else f", overhead {100 * (v / med['cli'] - 1):+.2f} %"
        print(f"  {k:13s} {v:.4f} s ({n * a.steps / v / 1e6:.2f} M particle-steps/s){over}")
    for k, v in within.items():
        print(f"  {k:13s} call against its own step loop: {100 * statistics.median(v):+.2f} % (median)")


if __name__ == "__main__":
    main()
