#!/usr/bin/env python3
"""LAMMPS's FIRE on a packing of frictionless disks in a periodic cell: the independent
reference for `dem2d relax` at the jamming threshold (issue 41, item 12).

Reads a dem2d case file of disks (circles only, a periodic "xy" cell, the linear law with no
dashpots, no friction, no gravity, `kn` given), writes it as a LAMMPS data file, minimises its
energy with LAMMPS's `min_style fire` (FIRE 2.0, Guénolé et al. 2020, LAMMPS's defaults:
semi-implicit Euler, half step back, tmax 10, tmin 0.02, delaystep 20, dtgrow 1.1, dtshrink 0.5,
alpha0 0.25, alphashrink 0.99) and reports, as one JSON object on standard output:

  energy          the potential energy at LAMMPS's end, Σ ½ k_n δ² over the pairs (erg per cm
                  of thickness), computed here from the final positions (LAMMPS's granular
                  styles tally no energy)
  residual        dem2d's residual measure computed here from the final positions: the largest
                  |net force| on a disk over the mean of Σ|f| over its contacts
  contacts, z, rattlers
                  contacts (pairs closer than r_i + r_j), and with rattlers (fewer than 3
                  contacts, removed repeatedly) left out: 2·contacts/kept and N − kept
  iterations      LAMMPS's minimisation iterations
  lammps_fnorm    LAMMPS's final force 2-norm

dem2d's linear law on a disk pair is F = k_n δ, U = ½ k_n δ² (δ = r_i + r_j − |x_i − x_j|; for
disks the area law's equivalent depth is δ itself); LAMMPS's `pair_style gran/hooke` with no
dashpots and no friction is F = k_n δ too (its Hookean normal force; the tangential force is
μ-capped, μ = 0). Masses are dem2d's (density × π r², a 1 cm slice: `set density/disc`); the
minimum does not depend on them, FIRE's path does a little. LAMMPS stops at its iteration cap
(ftol 0: the force norm is at its round-off level well before) or when FIRE's power stays
negative for 2000 steps (LAMMPS's own stop, "max vdotf<0").

Usage (LAMMPS from Debian's `lammps` package, 29 Sep 2021: `apt-get install lammps`, binary `lmp`):
  python3 lab/peers/jamming_fire.py cases/jammed_disks_256.json [--dt DT] [--lmp lmp]
     > lab/peers/jammed_disks_256.lammps.json
  python3 lab/peers/jamming_fire.py OUT/state.json --measure    (dem2d relax's result, measured
                                                                 the same way)
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile


def read_case(path):
    case = json.load(open(path))
    cell = case["cell"]
    assert cell.get("periodic") == "xy", "a cell periodic in x and y"
    contact = case["contact"]
    assert contact.get("friction", 0) == 0, "frictionless"
    assert all(g == 0 for g in case.get("gravity", [0, 0])), "no gravity"
    bodies = []
    for b in case["bodies"]:
        assert b["shape"]["type"] == "circle", "disks only"
        bodies.append((b["shape"]["r"], b["position"][0], b["position"][1], b.get("density", 1.0)))
    return case, cell["size"], float(contact["kn"]), bodies


def network(size, bodies, kn):
    """Forces, energy, contacts of the disks (brute force over pairs, nearest image)."""
    lx, ly = size
    n = len(bodies)
    force = [[0.0, 0.0] for _ in range(n)]
    acting = [0.0] * n
    energy = 0.0
    pairs = []
    for i in range(n):
        ri, xi, yi, _ = bodies[i]
        for j in range(i + 1, n):
            rj, xj, yj, _ = bodies[j]
            dx = xj - xi
            dy = yj - yi
            dx -= lx * round(dx / lx)
            dy -= ly * round(dy / ly)
            d = math.hypot(dx, dy)
            delta = ri + rj - d
            if delta > 0:
                f = kn * delta
                energy += 0.5 * kn * delta * delta
                ux, uy = dx / d, dy / d
                force[i][0] -= f * ux
                force[i][1] -= f * uy
                force[j][0] += f * ux
                force[j][1] += f * uy
                acting[i] += f
                acting[j] += f
                pairs.append((i, j))
    mean = sum(acting) / n
    residual = max(math.hypot(*f) for f in force) / mean if mean > 0 else 0.0
    alive = [True] * n
    while True:
        z = [0] * n
        for i, j in pairs:
            if alive[i] and alive[j]:
                z[i] += 1
                z[j] += 1
        gone = [k for k in range(n) if alive[k] and z[k] < 3]
        if not gone:
            break
        for k in gone:
            alive[k] = False
    kept = sum(alive)
    contacts = sum(z) // 2
    return {
        "energy": energy,
        "residual": residual,
        "contacts": len(pairs),
        "z": 2.0 * contacts / kept if kept else float("nan"),
        "rattlers": n - kept,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case")
    ap.add_argument("--dt", type=float, help="LAMMPS's timestep (default: the case's dt)")
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--maxiter", type=int, default=1_000_000)
    ap.add_argument(
        "--measure",
        action="store_true",
        help="no LAMMPS: the energy, residual and contacts of the file's own positions (a "
        "dem2d state.json, say)",
    )
    args = ap.parse_args()
    case, size, kn, bodies = read_case(args.case)
    if args.measure:
        json.dump(network(size, bodies, kn), sys.stdout, indent=1)
        print()
        return
    dt = args.dt or case["dt"]
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "packing.data")
        with open(data, "w") as f:
            f.write("dem2d case %s\n\n%d atoms\n1 atom types\n\n" % (case["name"], len(bodies)))
            f.write("0 %r xlo xhi\n0 %r ylo yhi\n-0.5 0.5 zlo zhi\n\n" % (size[0], size[1]))
            f.write("Atoms # sphere\n\n")
            for k, (r, x, y, rho) in enumerate(bodies):
                # (id type diameter density x y z; the mass is set per disk below.)
                f.write("%d 1 %r %r %r %r 0.0\n" % (k + 1, 2 * r, rho, x, y))
        dump = os.path.join(tmp, "final.txt")
        deck = [
            "units lj",
            "dimension 2",
            "boundary p p p",
            "atom_style sphere",
            "atom_modify map array",
            "comm_modify vel yes",
            "newton off",
            "read_data %s" % data,
        ]
        # Density × π r² (a 1 cm slice), dem2d's mass.
        for k, (_, _, _, rho) in enumerate(bodies):
            if rho != 1.0:
                deck.append("set atom %d density/disc %r" % (k + 1, rho))
        deck += [
            "set type 1 density/disc 1.0" if all(b[3] == 1.0 for b in bodies) else "",
            "pair_style gran/hooke %r NULL 0.0 0.0 0.0 0" % kn,
            "pair_coeff * *",
            "neighbor 0.3 bin",
            "neigh_modify every 1 delay 0 check yes",
            "timestep %r" % dt,
            "min_style fire",
            "thermo 100000",
            "thermo_style custom step fnorm fmax",
            "minimize 0.0 0.0 %d %d" % (args.maxiter, 10 * args.maxiter),
            'print "RESULT iterations $(step) fnorm $(fnorm:%.6g)"',
            "write_dump all custom %s id x y modify format float %%.17g sort id" % dump,
        ]
        deck_file = os.path.join(tmp, "in.fire")
        open(deck_file, "w").write("\n".join(deck) + "\n")
        run = subprocess.run(
            [args.lmp, "-in", deck_file, "-log", os.path.join(tmp, "log.lammps"), "-screen", "none"],
            capture_output=True,
            text=True,
            cwd=tmp,
        )
        log = open(os.path.join(tmp, "log.lammps")).read() if os.path.exists(os.path.join(tmp, "log.lammps")) else ""
        if run.returncode != 0:
            sys.exit("lmp failed: %s\n%s\n%s" % (run.returncode, run.stderr, log[-3000:]))
        m = re.search(r"^RESULT iterations (\d+) fnorm (\S+)", log, re.M)
        stop = re.search(r"Stopping criterion = (.*)", log)
        final = {}
        lines = open(dump).read().splitlines()
        start = lines.index(next(l for l in lines if l.startswith("ITEM: ATOMS"))) + 1
        for l in lines[start:]:
            k, x, y = l.split()
            final[int(k)] = (float(x), float(y))
        moved = [(b[0], final[k + 1][0], final[k + 1][1], b[3]) for k, b in enumerate(bodies)]
    out = {
        "case": case["name"],
        "lammps": "min_style fire (LAMMPS defaults), pair_style gran/hooke, timestep %r" % dt,
        "stopping_criterion": stop.group(1).strip() if stop else None,
        "iterations": int(m.group(1)),
        "lammps_fnorm": float(m.group(2)),
    }
    out.update(network(size, moved, kn))
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
