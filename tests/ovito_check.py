"""Reads `dem2d export`'s LAMMPS dumps with OVITO's own Python module and checks them against
the run's files, read here as text; renders the last frame offscreen and checks the picture.

    python ovito_check.py MIX_RUN CELL_RUN OUT.png

MIX_RUN holds a run of ellipses, disks, a rectangle and a polygon on a floor between two walls
with its `dump.lammpstrj`; CELL_RUN a run in a periodic cell under Lees–Edwards shear with its
dump. Checks (each against the run's `trajectory.csv`, `case.json`, `cell.csv`, not against
dem2d's code): the frame count, each frame's timestep and time; the identities (body + 1);
positions (to 1e-9 cm), velocities and spins; orientations — OVITO's quaternion turned back into
an angle about z equals the trajectory's angle modulo π for an ellipse, 2π for the others (to
2e-6 rad: OVITO keeps orientations in 32-bit floats); the Aspherical Shape of an ellipse (a, b),
of a disk (r, r), of the rectangle and the polygon (R, R) with R the bounding radius measured
here from the sides or the vertices (to 1e-6 relative: 32-bit floats too); the non-periodic box
holding every body; the sheared cell's vectors (L_x, 0), (tilt, L_y) with the tilt the image's
shift modulo L_x. Then Tachyon renders the last frame from above (white background, box
hidden): the picture is not blank, each body's centre is drawn, and each ellipse is drawn along
its own long axis — a point 0.8 a along it is coloured, a point 1.3 b across it is not. Prints
`ovito check passed: …`.
"""

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np
import ovito
from ovito.io import import_file
from ovito.vis import TachyonRenderer, Viewport


def fail(msg):
    print("ovito check FAILED:", msg)
    sys.exit(1)


def trajectory(run):
    """Per step (in order): the time as written and the rows (body, x, y, angle, vx, vy, ω)."""
    frames = []
    with open(run / "trajectory.csv", newline="") as f:
        for row in csv.DictReader(f):
            step = int(row["step"])
            if not frames or frames[-1][0] != step:
                frames.append((step, float(row["t"]), []))
            frames[-1][2].append(
                [float(row[k]) for k in ("body", "x", "y", "angle", "vx", "vy", "omega")]
            )
    return frames


def axes(shape):
    """(a, b, is_ellipse): an ellipse's semi-axes, a disk's (r, r), else the bounding radius."""
    t = shape["type"]
    if t == "circle":
        return shape["r"], shape["r"], False
    if t == "ellipse":
        return shape["a"], shape["b"], True
    if t == "rectangle":
        r = math.hypot(shape["w"], shape["h"]) / 2
        return r, r, False
    if t == "polygon":
        v = shape["vertices"]
        n = len(v)
        area = cx = cy = 0.0
        for i in range(n):
            (x0, y0), (x1, y1) = v[i], v[(i + 1) % n]
            c = x0 * y1 - x1 * y0
            area += c / 2
            cx += (x0 + x1) * c
            cy += (y0 + y1) * c
        cx, cy = cx / (6 * area), cy / (6 * area)
        r = max(math.hypot(x - cx, y - cy) for x, y in v)
        return r, r, False
    fail(f"no expectation for a {t}")


def wrap(d, period):
    return d - period * round(d / period)


def check_frames(run, pipeline, traj, bodies):
    if pipeline.source.num_frames != len(traj):
        fail(f"{run}: OVITO reads {pipeline.source.num_frames} frames, the trajectory has {len(traj)}")
    for k, (step, t, rows) in enumerate(traj):
        data = pipeline.compute(k)
        if data.attributes["Timestep"] != step:
            fail(f"frame {k}: timestep {data.attributes['Timestep']}, expected {step}")
        if abs(data.attributes["Time"] - t) > 1e-12 * max(1.0, t):
            fail(f"frame {k}: time {data.attributes['Time']}, expected {t}")
        p = data.particles
        rows = np.array(rows)
        ident = np.asarray(p["Particle Identifier"])
        order = np.argsort(ident)
        if not np.array_equal(ident[order], rows[:, 0].astype(int) + 1):
            fail(f"frame {k}: identifiers {ident[order]} vs bodies + 1 {rows[:, 0] + 1}")
        pos = np.asarray(p["Position"])[order]
        if np.abs(pos[:, :2] - rows[:, 1:3]).max() > 1e-9 or np.abs(pos[:, 2]).max() != 0:
            fail(f"frame {k}: positions differ by {np.abs(pos[:, :2] - rows[:, 1:3]).max()}")
        vel = np.asarray(p["Velocity"])[order]
        if np.abs(vel[:, :2] - rows[:, 4:6]).max() > 1e-9 * max(1.0, np.abs(rows[:, 4:6]).max()):
            fail(f"frame {k}: velocities differ")
        spin = np.asarray(p["Angular Velocity"])[order][:, 2]
        if np.abs(spin - rows[:, 6]).max() > 1e-9 * max(1.0, np.abs(rows[:, 6]).max()):
            fail(f"frame {k}: spins differ")
        quat = np.asarray(p["Orientation"], dtype=float)[order]  # (x, y, z, w)
        shape = np.asarray(p["Aspherical Shape"], dtype=float)[order]
        for m, row in enumerate(rows):
            body = int(row[0])
            a, b, ellipse = bodies[body]
            qx, qy, qz, qw = quat[m]
            if abs(qx) > 1e-7 or abs(qy) > 1e-7 or abs(qz * qz + qw * qw - 1) > 1e-6:
                fail(f"frame {k}, body {body}: quaternion {quat[m]} is not a turn about z")
            turn = 2 * math.atan2(qz, qw)
            period = math.pi if ellipse else 2 * math.pi
            if abs(wrap(turn - row[3], period)) > 2e-6:
                fail(f"frame {k}, body {body}: OVITO's angle {turn} vs {row[3]} (mod {period})")
            if abs(shape[m, 0] - a) > 1e-6 * a or abs(shape[m, 1] - b) > 1e-6 * b:
                fail(f"frame {k}, body {body}: Aspherical Shape {shape[m]} vs ({a}, {b})")
            if not 0 < shape[m, 2] < min(a, b):
                fail(f"frame {k}, body {body}: z semi-axis {shape[m, 2]} is not thin")
    return data


def main():
    mix, cell_run, png = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    case = json.loads((mix / "case.json").read_text())
    bodies = [axes(b["shape"]) for b in case["bodies"]]
    traj = trajectory(mix)
    pipeline = import_file(str(mix / "dump.lammpstrj"))
    data = check_frames(mix, pipeline, traj, bodies)
    # The box holds every body's bounding circle; no periodic direction.
    cell = np.asarray(data.cell[...])
    if tuple(data.cell.pbc) != (False, False, False):
        fail(f"pbc {data.cell.pbc}")
    lo, hi = cell[:2, 3], cell[:2, 3] + np.diag(cell[:2, :2])
    for row in traj[-1][2]:
        a, b, _ = bodies[int(row[0])]
        r = max(a, b)
        if not (lo[0] <= row[1] - r and row[1] + r <= hi[0] and lo[1] <= row[2] - r and row[2] + r <= hi[1]):
            fail(f"body {row[0]} sticks out of the box {lo}–{hi}")

    # The sheared periodic cell: vectors (Lx, 0) and (tilt, Ly), the tilt the offset mod Lx.
    cells = list(csv.DictReader(open(cell_run / "cell.csv", newline="")))
    ctraj = trajectory(cell_run)
    cp = import_file(str(cell_run / "dump.lammpstrj"))
    ccase = json.loads((cell_run / "case.json").read_text())
    check_frames(cell_run, cp, ctraj, [axes(b["shape"]) for b in ccase["bodies"]])
    tilted = 0
    for k, row in enumerate(cells):
        d = cp.compute(k)
        m = np.asarray(d.cell[...])
        lx, ly, off = float(row["lx"]), float(row["ly"]), float(row["offset"])
        if tuple(d.cell.pbc) != (True, True, False):
            fail(f"cell frame {k}: pbc {d.cell.pbc}")
        if abs(m[0, 0] - lx) > 1e-12 * lx or abs(m[1, 1] - ly) > 1e-12 * ly or m[1, 0] != 0:
            fail(f"cell frame {k}: {m} vs Lx {lx}, Ly {ly}")
        if abs(wrap(m[0, 1] - off, lx)) > 1e-9 * lx:
            fail(f"cell frame {k}: tilt {m[0, 1]} vs the image's shift {off} (mod {lx})")
        tilted += m[0, 1] != 0
    if tilted < 5:
        fail(f"only {tilted} sheared frames")

    # Render the last frame from above: world (x, y) is at pixel
    # (W/2 + k (x − cx), H/2 − k (y − cy)) with k = H / (2 fov) (an orthographic fov is half
    # the visible height).
    last = len(traj) - 1
    rows = traj[last][2]
    xs = [r[1] for r in rows]
    ys = [r[2] for r in rows]
    cx, cy = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2
    W, H, fov = 900, 450, 0.5 * (max(ys) - min(ys)) + 4.0
    fov = max(fov, 0.5 * (max(xs) - min(xs) + 8.0) * H / W)
    pipeline.add_to_scene()
    pipeline.source.data.cell.vis.enabled = False
    vp = Viewport(type=Viewport.Type.Ortho, camera_pos=(cx, cy, 50), camera_dir=(0, 0, -1), fov=fov)
    vp.render_image(size=(W, H), filename=png, background=(1, 1, 1), frame=last,
                    renderer=TachyonRenderer())
    from PySide6.QtGui import QImage

    img = QImage(png).convertToFormat(QImage.Format.Format_RGBA8888)
    pix = np.frombuffer(img.constBits(), np.uint8).reshape(H, img.bytesPerLine() // 4, 4)[:, :W, :3]
    drawn = (pix.astype(int).sum(axis=2) < 3 * 235)
    kpx = H / (2 * fov)

    def at(x, y):
        i, j = int(round(H / 2 - kpx * (y - cy))), int(round(W / 2 + kpx * (x - cx)))
        return bool(drawn[i, j])

    frac = drawn.mean()
    if frac < 0.01:
        fail(f"the render is blank ({frac:.4f} of its pixels drawn)")
    checked = 0
    for r in rows:
        body, x, y, th = int(r[0]), r[1], r[2], r[3]
        a, b, ellipse = bodies[body]
        if not at(x, y):
            fail(f"body {body}'s centre ({x}, {y}) is not drawn")
        if ellipse and a >= 1.5 * b:
            c, s = math.cos(th), math.sin(th)
            along = (x + 0.8 * a * c, y + 0.8 * a * s)
            across = (x - 1.3 * b * s, y + 1.3 * b * c)
            # (Only where no other body's bounding circle reaches.)
            clear = all(
                math.hypot(across[0] - o[1], across[1] - o[2]) > max(bodies[int(o[0])][:2])
                for o in rows if int(o[0]) != body
            )
            if not at(*along):
                fail(f"ellipse {body}: not drawn 0.8 a along its axis (angle {th})")
            if clear and at(*across):
                fail(f"ellipse {body}: drawn 1.3 b across its axis (angle {th})")
            checked += 1
    if checked < 2:
        fail(f"only {checked} ellipses checked in the picture")
    print(
        f"ovito check passed: {len(traj)} frames, {len(rows)} bodies; {len(cells)} sheared-cell "
        f"frames; render {W}x{H}, {frac:.3f} drawn, {checked} ellipses along their axes "
        f"(OVITO {'.'.join(map(str, ovito.version))})"
    )


main()
