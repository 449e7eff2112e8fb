"""Reads a dem2d run's VTK output with VTK's own readers and checks it against the run's other
files (case.json, trajectory.csv, increments.csv), which are written independently of the VTK
writer. Used by tests/vtk.rs; needs VTK's Python module (Debian: python3-vtk9).

    python3 tests/vtk_check.py RUN_DIR

A run whose bodies come and go (`insert`, `outflow`) is read as such: a frame's bodies are the
trajectory's rows at its step, each named by its identity (`body`), its shape the case's (a body
of the case) or its inserter's at the radius and aspect inserted.csv records (an inserted body).

Checks, for every frame listed in run.pvd:
- the frame's TIME equals the pvd's timestep and the trajectory's t at that step;
- cell counts: one polygon per body, one line per wall, one line per contact (the number of
  contacts of that step from increments.csv, for frames after step 0);
- each body polygon's area, as VTK computes it (vtkCellSizeFilter), against the body's exact
  area (pi a b, pi r^2, w h): inscribed, so smaller, by at most eps * b * perimeter with
  eps = 1e-3 (the outline's chord bound, src/output/outline.rs); rectangles exact to 1e-12;
- each polygon's area centroid against the body's position (within 1e-3 b);
- each polygon's vertices on the boundary of the body's own shape, placed at the trajectory's
  position and angle: a circle's at distance r, an ellipse's on (x'/a)^2 + (y'/b)^2 = 1, a
  rectangle's the four corners (1e-9 relative) — the outline drawn is the shape of the body
  that has that identity, whatever its index in the frame;
- ids, velocities, angular velocities and angles equal to the trajectory's (to the bit: both
  are the same doubles, the CSV in shortest round-trip form);
- the shape tensor against R diag(a^2, b^2) R^T computed here from the case's semi-axes and
  the trajectory's angle (1e-12 relative), and its eigenvalues a^2, b^2 (semi-axes, not
  diameters);
- contact lines join the centroids of the pair's bodies (or a body's centroid and a point on
  the wall); normals are unit; F_n = F.n >= 0 and F = F_n n + F_t t;
- wall lines run along the wall (perpendicular to its normal, through its point);
- in a periodic cell (cell.csv): the field data CELL_SIZE, CELL_OFFSET, CELL_SHIFT equal to
  cell.csv's row of that step (to the bit); the cell's outline (kind 3) is the closed poly-line
  (0, 0), (Lx, 0), (Lx, Ly), (0, Ly), (0, 0) at that row's size ("xy"), or the two seams x = 0
  and x = Lx ("x"); a contact line across a seam ends at an image of the giver's centroid (its
  centroid shifted by a period, with the Lees-Edwards offset across the y seam) no farther
  than half a period from the receiver.
Prints one line per frame and exits 1 at the first failure.
"""

import csv
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy

EPS = 1e-3  # the outline's largest chord distance, relative to the smaller semi-axis


def fail(msg):
    print(f"vtk check FAILED: {msg}")
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


def perimeter(a, b):
    # Ramanujan's second approximation (relative error below 1e-9 at a/b = 10): only a bound's
    # factor.
    h = ((a - b) / (a + b)) ** 2
    return math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))


def inserted_shape(spec, r, aspect):
    """The shape of an inserted body: its inserter's `shape` at radius r and aspect (see
    docs/src/reference/outputs.md, inserted.csv)."""
    kind = spec["shape"]
    if kind == "circle":
        return {"type": "circle", "r": r}
    if kind == "ellipse":
        return {"type": "ellipse", "a": r * math.sqrt(aspect), "b": r / math.sqrt(aspect)}
    if kind == "rectangle":
        return {"type": "rectangle", "w": r * math.sqrt(math.pi * aspect), "h": r * math.sqrt(math.pi / aspect)}
    fail(f"inserted shape {kind} is not checked here")


def on_boundary(shape, P, x, y, ang):
    """The largest distance of the points P from the boundary of `shape` at (x, y, ang), relative
    to its size (0 for points on it)."""
    cs, sn = math.cos(ang), math.sin(ang)
    worst = 0.0
    kind = shape["type"]
    local = [((p[0] - x) * cs + (p[1] - y) * sn, -(p[0] - x) * sn + (p[1] - y) * cs) for p in P]
    if kind == "circle":
        r = shape["r"]
        for u, v in local:
            worst = max(worst, abs(math.hypot(u, v) - r) / r)
    elif kind == "ellipse":
        a, b = shape["a"], shape["b"]
        for u, v in local:
            worst = max(worst, abs(math.sqrt((u / a) ** 2 + (v / b) ** 2) - 1))
    else:
        hw, hh = shape["w"] / 2, shape["h"] / 2
        if len(local) != 4:
            return math.inf
        for u, v in local:
            worst = max(worst, abs(abs(u) - hw) / hw, abs(abs(v) - hh) / hh)
    return worst


def main(run):
    case = json.load(open(os.path.join(run, "case.json")))
    # Every body's shape by its identity: the case's bodies, then the inserted ones.
    shapes = {k: b["shape"] for k, b in enumerate(case["bodies"])}
    inserted_path = os.path.join(run, "inserted.csv")
    if os.path.exists(inserted_path):
        with open(inserted_path) as f:
            for row in csv.DictReader(f):
                spec = case["insert"][int(row["insert"])]
                shapes[int(row["body"])] = inserted_shape(spec, float(row["r"]), float(row["aspect"]))
    walls = case.get("walls", [])
    nw = len(walls)
    traj = {}
    with open(os.path.join(run, "trajectory.csv")) as f:
        for row in csv.DictReader(f):
            traj.setdefault(int(row["step"]), []).append(row)
    contacts_at = {}
    with open(os.path.join(run, "increments.csv")) as f:
        for row in csv.DictReader(f):
            contacts_at[int(row["step"])] = int(row["contacts"])

    cellspec = case.get("cell")
    cells_at = {}
    if cellspec is not None:
        with open(os.path.join(run, "cell.csv")) as f:
            for row in csv.DictReader(f):
                cells_at[int(row["step"])] = row
    n_cell = 0 if cellspec is None else (1 if cellspec["periodic"] == "xy" else 2)

    pvd = ET.parse(os.path.join(run, "run.pvd")).getroot()
    datasets = pvd.findall("./Collection/DataSet")
    check(len(datasets) >= 2, f"run.pvd lists {len(datasets)} frames")
    total_cells = 0
    total_seam = 0
    for ds in datasets:
        path = os.path.join(run, ds.get("file"))
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        check(reader.GetErrorCode() == 0, f"{path}: VTK reader error {reader.GetErrorCode()}")
        grid = reader.GetOutput()
        fd = grid.GetFieldData()
        t = vtk_to_numpy(fd.GetArray("TIME"))[0]
        step = int(vtk_to_numpy(fd.GetArray("STEP"))[0])
        check(t == float(ds.get("timestep")), f"{path}: TIME {t} != pvd timestep {ds.get('timestep')}")
        rows = traj.get(step)
        check(rows is not None, f"{path}: step {step} is not a trajectory frame")
        nb = len(rows)
        bids = [int(row["body"]) for row in rows]
        check(float(rows[0]["t"]) == t, f"{path}: TIME {t} != trajectory t {rows[0]['t']}")

        cd = grid.GetCellData()
        arr = {cd.GetArrayName(i): vtk_to_numpy(cd.GetArray(i)) for i in range(cd.GetNumberOfArrays())}
        kind = arr["kind"]
        n_body, n_contact, n_wall, n_outline = (int((kind == k).sum()) for k in (0, 1, 2, 3))
        check(n_body == nb, f"{path}: {n_body} body cells, the trajectory has {nb} bodies")
        check(n_wall == nw, f"{path}: {n_wall} wall cells, case has {nw} walls")
        check(n_outline == n_cell, f"{path}: {n_outline} cell outlines, want {n_cell}")
        if step > 0:
            want = contacts_at[step]
            check(n_contact == want, f"{path}: {n_contact} contact cells, increments.csv says {want}")
        check(grid.GetNumberOfCells() == nb + n_contact + nw + n_outline, f"{path}: cell count")
        lx = ly = offset = None
        if cellspec is not None:
            row = cells_at.get(step)
            check(row is not None, f"{path}: step {step} is not a row of cell.csv")
            lx, ly, offset, shift = (float(row[k]) for k in ("lx", "ly", "offset", "shift"))
            size = vtk_to_numpy(fd.GetArray("CELL_SIZE"))
            check(size.shape == (1, 2) and size[0][0] == lx and size[0][1] == ly,
                  f"{path}: CELL_SIZE {size} != cell.csv ({lx}, {ly})")
            for name, want in (("CELL_OFFSET", offset), ("CELL_SHIFT", shift)):
                got = vtk_to_numpy(fd.GetArray(name))[0]
                check(got == want, f"{path}: {name} {got} != cell.csv {want}")
        else:
            check(fd.GetArray("CELL_SIZE") is None, f"{path}: CELL_SIZE without a cell")
        total_cells += grid.GetNumberOfCells()

        sizes = vtk.vtkCellSizeFilter()
        sizes.SetInputData(grid)
        sizes.ComputeAreaOn()
        sizes.Update()
        area = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Area"))
        pts = vtk_to_numpy(grid.GetPoints().GetData())

        worst_area = 0.0
        for k in range(nb):
            c = k  # bodies come first, in order
            check(grid.GetCellType(c) == vtk.VTK_POLYGON, f"{path}: cell {c} is not a polygon")
            row = rows[k]
            check(arr["id"][c] == bids[k], f"{path}: body cell {c} has id {arr['id'][c]}, the trajectory's row {k} is body {bids[k]}")
            x, y, ang = float(row["x"]), float(row["y"]), float(row["angle"])
            for name, col in (("angle", "angle"), ("angular_velocity", "omega")):
                check(arr[name][c] == float(row[col]), f"{path}: body {k} {name} {arr[name][c]} != {row[col]}")
            v = arr["velocity"][c]
            check(v[0] == float(row["vx"]) and v[1] == float(row["vy"]) and v[2] == 0.0,
                  f"{path}: body {k} velocity {v} != ({row['vx']}, {row['vy']})")
            shape = shapes[bids[k]]
            kind_name = shape["type"]
            if kind_name == "circle":
                a = b = shape["r"]
                exact = math.pi * a * a
            elif kind_name == "ellipse":
                a, b = shape["a"], shape["b"]
                exact = math.pi * a * b
            else:
                a, b = shape["w"] / 2, shape["h"] / 2
                exact = 4 * a * b
            want_kind = {"circle": 0, "ellipse": 1, "rectangle": 2}[kind_name]
            check(arr["shape"][c] == want_kind, f"{path}: body {k} shape {arr['shape'][c]}")
            check(tuple(arr["semi_axes"][c]) == (a, b), f"{path}: body {k} semi_axes {arr['semi_axes'][c]}")
            # Area: inscribed polygon, within the chord bound.
            err = exact - area[c]
            if kind_name == "rectangle":
                check(abs(err) <= 1e-12 * exact, f"{path}: rectangle {k} area {area[c]} != {exact}")
            else:
                bound = EPS * min(a, b) * perimeter(a, b)
                check(0 < err <= bound, f"{path}: body {k} ({kind_name} {a}x{b}) polygon area {area[c]}, "
                      f"body {exact}: short by {err:e}, bound {bound:e}")
            worst_area = max(worst_area, abs(err) / exact)
            # Area centroid of the polygon (shoelace) at the body's position.
            cell = grid.GetCell(c)
            ids = [cell.GetPointId(i) for i in range(cell.GetNumberOfPoints())]
            P = pts[ids]
            xs, ys = P[:, 0], P[:, 1]
            xn, yn = list(xs[1:]) + [xs[0]], list(ys[1:]) + [ys[0]]
            cr = [xs[i] * yn[i] - xn[i] * ys[i] for i in range(len(xs))]
            A = sum(cr) / 2
            cx = sum((xs[i] + xn[i]) * cr[i] for i in range(len(xs))) / (6 * A)
            cy = sum((ys[i] + yn[i]) * cr[i] for i in range(len(xs))) / (6 * A)
            check(abs(A - area[c]) <= 1e-9 * exact, f"{path}: shoelace {A} != VTK area {area[c]}")
            check(math.hypot(cx - x, cy - y) <= 1e-3 * min(a, b), f"{path}: body {k} polygon centroid "
                  f"({cx}, {cy}) far from ({x}, {y})")
            off = on_boundary(shape, P, x, y, ang)
            check(off <= 1e-9, f"{path}: body {bids[k]}'s outline is not its {kind_name} {shape}: "
                  f"a vertex {off:.3g} off its boundary")
            # Shape tensor R diag(a^2, b^2) R^T, semi-axes.
            T = arr["shape_tensor"][c].reshape(3, 3)
            cs, sn = math.cos(ang), math.sin(ang)
            want = [[a * a * cs * cs + b * b * sn * sn, (a * a - b * b) * cs * sn, 0],
                    [(a * a - b * b) * cs * sn, a * a * sn * sn + b * b * cs * cs, 0],
                    [0, 0, 0]]
            for i in range(3):
                for j in range(3):
                    check(abs(T[i][j] - want[i][j]) <= 1e-12 * a * a,
                          f"{path}: body {k} shape tensor {T.tolist()} != {want}")
            tr, det = T[0][0] + T[1][1], T[0][0] * T[1][1] - T[0][1] * T[1][0]
            disc = math.sqrt(max(tr * tr / 4 - det, 0))
            ev = sorted([tr / 2 - disc, tr / 2 + disc])
            check(abs(ev[0] - min(a, b) ** 2) <= 1e-9 * a * a and abs(ev[1] - max(a, b) ** 2) <= 1e-9 * a * a,
                  f"{path}: body {k} tensor eigenvalues {ev}, semi-axes {a}, {b}")

        centroid = {bids[k]: (float(rows[k]["x"]), float(rows[k]["y"])) for k in range(nb)}
        n_seam = 0
        for c in range(grid.GetNumberOfCells()):
            if kind[c] == 1:
                check(grid.GetCellType(c) == vtk.VTK_LINE, f"{path}: contact cell {c} is not a line")
                cell = grid.GetCell(c)
                p0, p1 = pts[cell.GetPointId(0)], pts[cell.GetPointId(1)]
                i, j = arr["pair"][c]
                check(i in centroid, f"{path}: contact {c} pair {i}, {j}")
                check(tuple(p0[:2]) == centroid[i], f"{path}: contact {c} starts at {p0}, not body {i}'s centroid")
                n = arr["normal"][c]
                check(abs(math.hypot(n[0], n[1]) - 1) < 1e-12, f"{path}: contact {c} normal {n}")
                if j >= 0 and cellspec is not None and tuple(p1[:2]) != centroid[j]:
                    # Across a seam: an image of j's centroid, within half a period of i's.
                    dx, dy = p1[0] - centroid[j][0], p1[1] - centroid[j][1]
                    ky = round(dy / ly) if cellspec["periodic"] == "xy" else 0
                    check(abs(dy - ky * ly) <= 1e-9 * ly, f"{path}: contact {c} image {p1} off by {dy} in y")
                    kx = (dx - ky * offset) / lx
                    check(abs(kx - round(kx)) <= 1e-9 * max(1, abs(kx)) and (kx, ky) != (0, 0),
                          f"{path}: contact {c} image {p1} is not a periodic image of body {j}")
                    check(abs(p1[0] - p0[0]) <= lx / 2 and abs(p1[1] - p0[1]) <= (ly / 2 if ky else ly),
                          f"{path}: contact {c} image {p1} not the nearest to body {i}")
                    n_seam += 1
                elif j >= 0:
                    check(tuple(p1[:2]) == centroid[j], f"{path}: contact {c} ends at {p1}, not body {j}'s centroid")
                else:
                    w = walls[-1 - j]
                    wp, wn = w["point"], w["normal"]
                    norm = math.hypot(*wn)
                    dist = ((p1[0] - wp[0]) * wn[0] + (p1[1] - wp[1]) * wn[1]) / norm
                    check(abs(dist) <= 0.05 * max(shapes[i].get(s, 0) for s in "rabwh"),
                          f"{path}: wall contact {c} point {p1} is {dist} from wall {-1 - j}")
                fn, ft, F = arr["normal_force"][c], arr["tangential_force"][c], arr["force"][c]
                check(fn >= 0, f"{path}: contact {c} pulls: F_n = {fn}")
                tan = (-n[1], n[0])
                rx, ry = fn * n[0] + ft * tan[0] - F[0], fn * n[1] + ft * tan[1] - F[1]
                check(math.hypot(rx, ry) <= 1e-12 * max(math.hypot(F[0], F[1]), 1e-300),
                      f"{path}: contact {c} F != F_n n + F_t t")
            elif kind[c] == 2:
                check(grid.GetCellType(c) == vtk.VTK_LINE, f"{path}: wall cell {c} is not a line")
                cell = grid.GetCell(c)
                p0, p1 = pts[cell.GetPointId(0)], pts[cell.GetPointId(1)]
                w = walls[arr["id"][c]]
                wp, wn = w["point"], w["normal"]
                norm = math.hypot(*wn)
                for p in (p0, p1):
                    d = ((p[0] - wp[0]) * wn[0] + (p[1] - wp[1]) * wn[1]) / norm
                    check(abs(d) <= 1e-9 * max(1.0, abs(p[0]), abs(p[1])), f"{path}: wall {arr['id'][c]} line point {p} off the wall by {d}")
            elif kind[c] == 3:
                outline = grid.GetCell(c)
                P = [tuple(pts[outline.GetPointId(i)][:2]) for i in range(outline.GetNumberOfPoints())]
                if cellspec["periodic"] == "xy":
                    check(grid.GetCellType(c) == vtk.VTK_POLY_LINE, f"{path}: cell outline {c} is not a poly-line")
                    want = [(0, 0), (lx, 0), (lx, ly), (0, ly), (0, 0)]
                    check(P == want, f"{path}: cell outline {P} != {want}")
                else:
                    check(grid.GetCellType(c) == vtk.VTK_LINE, f"{path}: cell seam {c} is not a line")
                    check(P[0][0] == P[1][0] and P[0][0] in (0.0, lx) and P[0][1] < P[1][1],
                          f"{path}: cell seam {P} is not x = 0 or x = {lx}")
        print(f"{ds.get('file')}: step {step}, t = {t}: {nb} bodies, {n_contact} contacts, {nw} walls, {n_outline} cell outlines, {n_seam} contacts across a seam; "
              f"largest polygon area deficit {worst_area:.2e} of the body's")
        total_seam += n_seam
    print(f"vtk check passed: {len(datasets)} frames, {total_cells} cells, {total_seam} contacts across a seam")


if __name__ == "__main__":
    main(sys.argv[1])
