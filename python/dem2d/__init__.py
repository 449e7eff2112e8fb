"""dem2d from Python: build a scene, run it, and read its state as numpy arrays.

Units are cgs (cm, g, s; forces in dyn and energies in erg per cm of thickness), angles in
radians, counter-clockwise. A case is the case file's JSON (docs: reference/case-file.md) as a
dict; the run is the library's run driver, writing the same files as `dem2d run` when given an
output directory.

    import dem2d
    case = dem2d.Case.load("cases/settle3_dt1e-5.json")
    sim = dem2d.Simulation(case, threads=2, out="runs/settle3")
    sim.run()                      # to the case's duration, as `dem2d run`
    print(sim.positions[:3], sim.analysis()["packing_fraction"])
    run = dem2d.load_run("runs/settle3")
    print(run.positions.shape)     # (frames, bodies, 2)
"""

import json
import math
from pathlib import Path

from ._core import Case, Simulation, __version__, animate, export
from ._core import fields as _fields
from ._core import forces as _forces
from ._core import load_run as _load_run
from ._errors import BlowupError, Error, InputError, OutputError, RunError

__all__ = [
    "Case",
    "Simulation",
    "Run",
    "load_run",
    "export",
    "animate",
    "Error",
    "InputError",
    "RunError",
    "BlowupError",
    "OutputError",
    "circle",
    "ellipse",
    "rectangle",
    "polygon",
    "clump",
    "body",
    "wall",
    "insert",
    "outflow",
    "__version__",
]


# Shapes and bodies as the case file writes them (dicts; numpy values allowed).


def circle(r):
    """A disk of radius `r` (cm)."""
    return {"type": "circle", "r": r}


def ellipse(a, b):
    """An ellipse with semi-axes `a` (along the body's x axis) and `b` (cm)."""
    return {"type": "ellipse", "a": a, "b": b}


def rectangle(w, h):
    """A rectangle of full width `w` and height `h` (cm)."""
    return {"type": "rectangle", "w": w, "h": h}


def polygon(vertices):
    """A convex polygon, vertices counter-clockwise (cm; any origin: the body's position is its
    centroid)."""
    return {"type": "polygon", "vertices": [[x, y] for x, y in vertices]}


def clump(disks):
    """A rigid clump of disks given as (x, y, r) rows (cm)."""
    return {"type": "clump", "disks": [{"center": [x, y], "r": r} for x, y, r in disks]}


def body(shape, position, angle=None, velocity=None, omega=None, density=None):
    """A body of `shape` at `position` (its centroid); the keys left None take the case file's
    defaults (angle 0, at rest, density 1 g/cm²)."""
    b = {"shape": shape, "position": [position[0], position[1]]}
    for key, value in (
        ("angle", angle),
        ("velocity", None if velocity is None else [velocity[0], velocity[1]]),
        ("omega", omega),
        ("density", density),
    ):
        if value is not None:
            b[key] = value
    return b


def wall(point, normal, **keys):
    """A wall through `point` with unit `normal` pointing into the free side; `keys` are the
    case file's other wall keys (friction, velocity, servo, contact overrides)."""
    return {"point": [point[0], point[1]], "normal": [normal[0], normal[1]], **keys}


def insert(region, size, rate=None, count=None, keep=None, **keys):
    """An inserter (the case file's `insert[]`): bodies poured into `region` = (x0, x1, y0, y1)
    (cm) of equal-area radius `size` (a number, or a distribution such as
    `{"uniform": [lo, hi]}`), at `rate` bodies/s, or `count` at once, or keeping `keep` free
    bodies in the scene; `keys` are its other keys (shape, aspect, angle, velocity, seed, …).
    This and `outflow` with `body` and `wall` are the scene builder: a box, a silo or a periodic
    cell poured from above is a case dict (docs: reference/case-file.md)."""
    d = {"region": [region[0], region[1], region[2], region[3]], "size": size}
    for key, value in (("rate", rate), ("count", count), ("keep", keep)):
        if value is not None:
            d[key] = value
    d.update(keys)
    return d


def outflow(region):
    """An outflow region (the case file's `outflow[]`): the bodies whose centroids enter
    `region` = (x0, x1, y0, y1) (cm) are removed and logged to `discharge.csv`."""
    return {"region": [region[0], region[1], region[2], region[3]]}


# Reading a run directory.


def _read_csv(path):
    """A CSV table with a header as a dict of columns: numpy arrays where every field is a
    number (an empty field is NaN), lists of strings otherwise. A last line without its newline
    (a run stopped while writing) is left out."""
    import numpy as np

    text = Path(path).read_text(encoding="utf-8")
    lines = text.split("\n")
    # The last element is "" for a file ending in a newline, or a line cut short.
    header, rows = lines[0].split(","), [line.split(",") for line in lines[1:-1]]
    table = {}
    for k, name in enumerate(header):
        column = [row[k] if k < len(row) else "" for row in rows]
        try:
            table[name] = np.array([float(v) if v else math.nan for v in column])
        except ValueError:
            table[name] = column
    return table


def _series(table, key):
    """A long table (a row per step and `key`) as (F, K) arrays, a column per value of `key`
    in its order of first appearance; `step` and `t` (F,), `key` (K,). A frame cut short (the
    last one, of a run stopped while writing) is left out."""
    import numpy as np

    step, keys = table["step"], table[key]
    order = list(dict.fromkeys(keys.tolist()))
    k = len(order)
    f = len(step) // k if k else 0
    out = {"step": step[: f * k : k].astype(np.int64), "t": table["t"][: f * k : k],
           key: np.array(order, dtype=np.int64)}
    for name, column in table.items():
        if name in ("step", "t", key) or not isinstance(column, np.ndarray):
            continue
        out[name] = column[: f * k].reshape(f, k)
    return out


class Run:
    """A run directory read back without running it again (`dem2d::output::run_data`).

    Frames of `trajectory.csv`: `step` (F,), `t` (F,), `positions` (F, N, 2), `angles` (F, N),
    `velocities` (F, N, 2), `spins` (F, N). Column k is the body of identity `ids[k]`
    (`trajectory.csv`'s `body`; `0 … N − 1` unless the case inserts or removes bodies); where
    it does (`insert`, `outflow`), N counts every body that was ever present, `present` (F, N)
    says which are present in each frame, and an absent body's entries are NaN.
    `increments`: `increments.csv`'s columns.
    `contacts`: `contacts.csv`'s rows as arrays (`step`, `i` (-1 for a wall), `wall`, `j`,
    `point`, `normal`, `depth`, `force`, `fn`, `ft`, `couple`, `state`), None without the file.
    `analysis`, `walls` and `reactions`: the columns of `analysis.csv`, `walls.csv` and
    `reactions.csv` (the prescribed bodies' loads), None without them; `wall_series()` and
    `reaction_series()` give them as (F, W) arrays, a column per wall or prescribed body.
    In a periodic cell: `images` (F, N, 2), the bodies' image counts, `cell` the columns of
    `cell.csv`, and `unwrapped_positions` (F, N, 2); None without a cell.
    `summary`: `summary.json` as a dict. `case`: `case.json`; `state`: `state.json` as a Case
    (give it to `Simulation` to continue the run), None without it. `incomplete`: what was
    left out of files that end part-way through a line or a frame.
    """

    def __init__(self, path):
        self.path = Path(path)
        d = _load_run(self.path)
        self.step = d["step"]
        self.t = d["t"]
        self.positions = d["positions"]
        self.angles = d["angles"]
        self.velocities = d["velocities"]
        self.spins = d["spins"]
        self.ids = d["ids"]
        self.present = d["present"]
        self.increments = d["increments"]
        self.summary = json.loads(d["summary"])
        self.incomplete = d["incomplete"]
        self.contacts = d.get("contacts")
        self.case = Case.load(self.path / "case.json")
        analysis = self.path / "analysis.csv"
        self.analysis = _read_csv(analysis) if analysis.exists() else None
        walls = self.path / "walls.csv"
        self.walls = _read_csv(walls) if walls.exists() else None
        reactions = self.path / "reactions.csv"
        self.reactions = _read_csv(reactions) if reactions.exists() else None
        self.images = d.get("images")
        cell = self.path / "cell.csv"
        self.cell = _read_csv(cell) if self.images is not None and cell.exists() else None
        state = self.path / "state.json"
        self.state = Case.load(state) if state.exists() else None

    @property
    def unwrapped_positions(self):
        """The positions unwrapped through the cell's seams, (F, N, 2): `x + ix lx + iy shift`,
        `y + iy ly` with the frame's cell size and total shift from `cell.csv` (None without a
        cell)."""
        if self.images is None or self.cell is None:
            return None
        import numpy as np

        rows = {int(s): k for k, s in enumerate(self.cell["step"])}
        at = np.array([rows[int(s)] for s in self.step], dtype=int)
        lx, ly, shift = (self.cell[k][at][:, None] for k in ("lx", "ly", "shift"))
        ix, iy = self.images[..., 0], self.images[..., 1]
        out = self.positions.copy()
        out[..., 0] += ix * lx + iy * shift
        out[..., 1] += iy * ly
        return out

    def wall_series(self):
        """`walls.csv` as (F, W) arrays: `step` and `t` (F,), every other column (`x`, `y`,
        `nx`, `ny`, `vx`, `vy`, `fn`, `ft`, `contacts`, `fx`, `fy`, `angle`, `omega`, `torque`,
        `power`, ...) with a column per wall in the case's order. None without the file."""
        return None if self.walls is None else _series(self.walls, "wall")

    def reaction_series(self):
        """`reactions.csv` as (F, B) arrays: `step` and `t` (F,), `body` (B,) the prescribed
        bodies' identities, every other column (`x`, `y`, `angle`, `fx`, `fy`, `moment`,
        `power`) with a column per prescribed body. None without the file."""
        return None if self.reactions is None else _series(self.reactions, "body")

    def export(self, format="lammps-dump", out=None):
        """`dem2d export`: the run's LAMMPS-style dump for OVITO (default `RUN/dump.lammpstrj`);
        returns its path."""
        return export(self.path, format, out)

    def animate(self, out=None, **options):
        """`dem2d animate`: the run as a self-contained HTML player (default
        `RUN/animation.html`), or a movie (`.mp4`, `.gif`, through ffmpeg); `options` are
        `every`, `color`, `fps`, `width` (see `dem2d.animate`). Returns its path."""
        return animate(self.path, out, **options)

    def fields(self, axis="y", bins=20, start=None, end=None, range=None, relative=False,
               out=None):
        """`dem2d fields`: the run's coarse-grained fields in `bins` slabs along `axis`, averaged
        over the frames with `start <= t <= end` (s), as a dict of numpy arrays (the columns of
        `fields.csv`: `y` or `x`, `phi`, `vx`, `vy`, `temperature`, `sxx`, `syy`, `sxy`,
        `nematic`, `frames`; NaN where empty). Also writes `fields.csv` (or `out`)."""
        path = _fields(self.path, axis=axis, bins=bins, start=start, end=end, range=range,
                       relative=relative, out=out)
        return _read_csv(path)

    def forces(self, frame=None, start=None, bins=40):
        """`dem2d forces`: the normal-force distribution and the stress-fabric check of the
        run's frame `frame` (default the last), or of every frame from `start` (s), or of a
        relaxed directory's state. Writes `forces.csv` and `forces.json`; returns
        `forces.json` as a dict with `distribution`, the columns of `forces.csv` (`f_over_mean`,
        `pdf`, `count`)."""
        _forces(self.path, frame=frame, start=start, bins=bins)
        out = json.loads((self.path / "forces.json").read_text())
        out["distribution"] = _read_csv(self.path / "forces.csv")
        return out

    @property
    def status(self):
        """The summary's status (`completed`, `at_rest`, `max_steps`, `interrupted`, ...)."""
        return self.summary.get("status")

    def __repr__(self):
        return (
            f"dem2d.Run({str(self.path)!r}, status={self.status!r}, frames={len(self.step)}, "
            f"bodies={self.positions.shape[1] if len(self.step) else 0})"
        )


def load_run(path):
    """Reads the run directory `path` (written by `dem2d run` or by a Simulation with `out=`)."""
    return Run(path)
