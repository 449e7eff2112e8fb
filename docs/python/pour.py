"""Pour a pile of ellipses from Python, let it settle, and plot its packing fraction against the
depth below its surface (the tutorial of docs/src/tutorials/python.md).

    pip install ./python matplotlib
    python docs/python/pour.py --out runs/pour --figure figures/python_pour.png

Without matplotlib it prints the profile only. `--steps N` stops the pour after N steps (a
quick look; the tests run it so).
"""

import argparse
import math
import time

import numpy as np

import dem2d


def pour(n, seed, width):
    """A case: n ellipses (a/b = 1.5, areas of disks of radius 0.8-1.2 cm, random orientations)
    on a jittered lattice above a floor between two walls, released at rest."""
    rng = np.random.default_rng(seed)
    columns = int(width // 3.0)
    bodies = []
    for k in range(n):
        r = rng.uniform(0.8, 1.2)
        row, col = divmod(k, columns)
        x = 1.5 + 3.0 * col + rng.uniform(-0.2, 0.2)
        y = 1.5 + 3.0 * row + rng.uniform(-0.2, 0.2)
        shape = dem2d.ellipse(r * math.sqrt(1.5), r / math.sqrt(1.5))
        bodies.append(dem2d.body(shape, (x, y), angle=rng.uniform(0, math.pi), density=2.65))
    return dem2d.Case(
        {
            "version": 1,
            "name": "pour",
            "description": f"{n} ellipses poured into a box {width} cm wide (docs/python/pour.py)",
            "units": "cm",
            "gravity": [0, -980],
            "dt": 1e-5,
            "duration": 3.0,
            # At rest: mean increments below 1e-7 cm per step (0.01 cm/s) for 1000 steps.
            "quiescence": 1e-7,
            "quiescence_window": 1000,
            "output_every": 5000,
            # P's stiffness, a dashpot giving restitution 0.5 to an r = 1 cm grain on a wall
            # (the `dem2d generate` piles' law), friction 0.3, the area law.
            "contact": {
                "model": "linear",
                "normal_force": "area",
                "kn_over_rho_g": 36400,
                "ks_over_rho_g": 36400,
                "eta_n": 12088.394294,
                "eta_s": 12088.394294,
                "friction": 0.3,
            },
            "walls": [
                dem2d.wall((0, 0), (0, 1)),
                dem2d.wall((0, 0), (1, 0)),
                dem2d.wall((width, 0), (-1, 0)),
            ],
            "bodies": bodies,
        }
    )


def profile(sim, width, slab):
    """Packing fraction of horizontal slabs `slab` cm thick, away from the side walls by 4 cm,
    from the floor to the pile's top: (depth of each slab's centre below the surface, φ)."""
    shapes = sim.shapes()
    top = (sim.positions[:, 1] + shapes["bounding_radius"]).max()
    rows = []
    y = 0.0
    while y + 0.5 * slab < top:
        a = sim.analysis(window=(4.0, width - 4.0, y, y + slab))
        rows.append((top - (y + 0.5 * slab), a["packing_fraction"]))
        y += slab
    return top, rows


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=600, help="grains (default 600)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--width", type=float, default=60.0, help="box width, cm (default 60)")
    p.add_argument("--threads", type=int, default=None)
    p.add_argument("--steps", type=int, default=None, help="stop after this many steps")
    p.add_argument("--out", default=None, help="write the run's files here (as dem2d run)")
    p.add_argument("--figure", default=None, help="save the plot here (needs matplotlib)")
    args = p.parse_args()

    case = pour(args.n, args.seed, args.width)
    sim = dem2d.Simulation(case, threads=args.threads, out=args.out, overwrite=True, analysis=True)
    start = time.perf_counter()
    # Until rest (the case's criterion), at most its duration, in parts of 0.1 s of simulated
    # time so that the progress can be printed.
    status = None
    while status not in ("at_rest", "interrupted") and sim.step < case.steps:
        left = case.steps - sim.step
        if args.steps is not None:
            left = min(left, args.steps - sim.step)
            if left <= 0:
                break
        status = sim.run(min(10_000, left))
        e = sim.energies()
        speed = np.sqrt((sim.velocities**2).sum(axis=1)).mean()
        print(f"t = {sim.time:.2f} s: {status}, mean speed {speed:.3g} cm/s, E_k = {e['kinetic']:.4g} erg")
    wall = time.perf_counter() - start
    print(f"{case.n_bodies} ellipses: {status} at t = {sim.time:.4f} s (step {sim.step}), {wall:.1f} s of wall time")

    a = sim.analysis(window=(4.0, args.width - 4.0, 2.0, 20.0))
    print(
        f"inside the pile (x in [4, {args.width - 4:g}], y in [2, 20] cm): packing fraction "
        f"{a['packing_fraction']:.3f}, coordination {a['coordination']:.2f}, "
        f"a_c {a['fabric']['a_c']:.2f} at {math.degrees(a['fabric']['theta_c']):.0f} deg"
    )
    top, rows = profile(sim, args.width, slab=2.0)
    print(f"surface at y = {top:.2f} cm")
    print("depth (cm)  packing fraction")
    for depth, phi in rows:
        print(f"{depth:10.1f}  {phi:.3f}")

    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        depth, phi = np.array(rows).T
        fig, ax = plt.subplots(figsize=(5, 4), dpi=150)
        ax.plot(phi, depth, "o-", ms=4)
        ax.invert_yaxis()
        ax.set_xlabel("packing fraction φ of a 2 cm slab")
        ax.set_ylabel("depth of the slab's centre below the surface (cm)")
        ax.set_xlim(0, 1)
        ax.set_title(f"{case.n_bodies} ellipses (a/b = 1.5) poured and settled", fontsize=10)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(args.figure)
        print(f"figure: {args.figure}")


if __name__ == "__main__":
    main()
