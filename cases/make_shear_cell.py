"""Writes cases/shear_cell.json, the periodic-shear tutorial's case (docs/src/tutorials/shear-cell.md):
150 disks, half of radius 5/12 cm and half of 7/12 cm (diameter ratio 1.4, mean diameter 1 cm),
drawn at random (seed 1) onto a 10 x 15 lattice (spacings 1.25 and 4/3 cm) in a 12.5 x 20 cm cell
periodic in x and y, moving with the shear's mean flow 3 (y - 10) cm/s plus random velocities up
to 1 cm/s, sheared at 3 /s under an imposed pressure of 1000 dyn/cm. Run: python3 cases/make_shear_cell.py > cases/shear_cell.json

With --compress, the same grains without friction and without shear, at rest but for the random
velocities, compressed for 3 s at 5000 dyn/cm: a jammed frictionless packing for `dem2d relax`.
Run: python3 cases/make_shear_cell.py --compress > cases/compress_cell_mu0.json

With --ellipses (alone or with --compress), the same grains as ellipses of aspect ratio 2 and the
disks' areas (a = r sqrt 2, b = r / sqrt 2), standing upright on a lattice stretched to 2 cm
rows (a 12.5 x 30 cm cell, which the imposed pressure closes): docs/src/results/fields-forces.md.
Run: python3 cases/make_shear_cell.py --ellipses > cases/shear_cell_ellipses.json
     python3 cases/make_shear_cell.py --compress --ellipses > cases/compress_cell_ellipses_mu0.json
"""
import json
import math
import random
import sys

compress = "--compress" in sys.argv[1:]
ellipses = "--ellipses" in sys.argv[1:]

rng = random.Random(1)
nx, ny, lx, ly, rate = 10, 15, 12.5, (30.0 if ellipses else 20.0), 3.0
radii = [5 / 12] * 75 + [7 / 12] * 75
rng.shuffle(radii)
bodies = []
for k, r in enumerate(radii):
    i, j = k % nx, k // nx
    x, y = (i + 0.5) * lx / nx, (j + 0.5) * ly / ny
    shape = {"type": "circle", "r": round(r, 12)}
    if ellipses:
        shape = {"type": "ellipse", "a": round(r * 2**0.5, 12), "b": round(r / 2**0.5, 12)}
    bodies.append({
        "shape": shape,
        "position": [round(x, 12), round(y, 12)],
        **({"angle": round(math.pi / 2, 12)} if ellipses else {}),
        "velocity": [round((0 if compress else rate * (y - ly / 2)) + rng.uniform(-1, 1), 6),
                     round(rng.uniform(-1, 1), 6)],
    })
case = {
    "version": 1,
    "name": "shear_cell",
    "description": "Lees-Edwards simple shear at imposed pressure: 150 frictional disks (diameter "
    "ratio 1.4, mean diameter 1 cm, density 1), gamma_dot = 3 /s, P = 1000 dyn/cm, I about 0.1; "
    "made by cases/make_shear_cell.py (docs: tutorials/shear-cell.md)",
    "units": "cm",
    "gravity": [0, 0],
    "dt": 5e-5,
    "duration": 2.0,
    "output_every": 400,
    "output": {"analysis": True},
    "cell": {"size": [lx, ly], "periodic": "xy", "shear_rate": rate, "pressure": 1000},
    "contact": {"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0.4},
    "bodies": bodies,
}
if compress:
    case["name"] = "compress_cell_mu0"
    case["description"] = ("A frictionless packing compressed in a periodic cell at P = 5000 dyn/cm "
                           "(the shear tutorial's grains, no shear): relax its end state with dem2d "
                           "relax; made by cases/make_shear_cell.py --compress")
    case["duration"] = 3.0
    case["output"] = {}
    case["cell"] = {"size": [lx, ly], "periodic": "xy", "pressure": 5000}
    case["contact"]["friction"] = 0
if ellipses:
    case["name"] = "compress_cell_ellipses_mu0" if compress else "shear_cell_ellipses"
    case["description"] = case["description"].replace("disks (diameter", "ellipses of aspect ratio 2 (equal-area diameter").replace(
        "grains", "grains as ellipses of aspect ratio 2 and the same areas") + " --ellipses"
text = json.dumps(case, indent=1)
print(text)
