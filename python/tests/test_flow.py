"""Pouring from Python: a case built with `insert` and `outflow` runs as the command line runs
it, inserts ⌊rate · t⌋ bodies and logs each removed body once."""

import json
import math
from pathlib import Path

import dem2d
from conftest import cli


def falling_case():
    return {
        "version": 1,
        "name": "python_pour",
        "gravity": [0, -981],
        "dt": 1e-4,
        "duration": 0.15,
        "contact": {"model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.3},
        "bodies": [],
        "insert": [
            dem2d.insert((-10, 10, 0, 4), {"uniform": [0.3, 0.5]}, rate=700, shape="ellipse",
                         aspect=2, velocity=[0, -500], seed=4)
        ],
        "outflow": [dem2d.outflow((-20, 20, -1000, -20))],
    }


def test_a_poured_case_inserts_at_its_rate_and_logs_what_leaves(tmp_path):
    case = dem2d.Case(falling_case())
    sim = dem2d.Simulation(case, out=tmp_path / "py")
    sim.run()
    inserted = math.floor(700 * sim.time)
    rows = (tmp_path / "py" / "discharge.csv").read_text().splitlines()[1:]
    ids = [int(r.split(",")[2]) for r in rows]
    assert len(set(ids)) == len(ids) > 10
    assert sim.n_bodies + len(rows) == inserted
    # The command line writes the same files.
    case.save(tmp_path / "case.json")
    cli("run", tmp_path / "case.json", "--out", tmp_path / "cli")
    for name in ("discharge.csv", "trajectory.csv"):
        assert (tmp_path / "cli" / name).read_text() == (tmp_path / "py" / name).read_text()


def _rows(path):
    """A CSV file as a header and its rows of strings, read with the standard library (not with
    dem2d's reader, which these tests check)."""
    import csv

    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def test_load_run_reads_a_poured_run_by_identity(tmp_path):
    import numpy as np

    case = dem2d.Case(dict(falling_case(), output_every=50))
    dem2d.Simulation(case, out=tmp_path).run()
    run = dem2d.load_run(tmp_path)
    header, rows = _rows(tmp_path / "trajectory.csv")
    col = {name: k for k, name in enumerate(header)}
    steps = sorted({int(r[col["step"]]) for r in rows})
    ids = sorted({int(r[col["body"]]) for r in rows})
    assert run.step.tolist() == steps and run.ids.tolist() == ids
    assert run.positions.shape == (len(steps), len(ids), 2)
    # Every row of trajectory.csv is where its step and identity say, and nothing else is there.
    seen = np.zeros(run.present.shape, dtype=bool)
    for r in rows:
        k, c = steps.index(int(r[col["step"]])), ids.index(int(r[col["body"]]))
        seen[k, c] = True
        assert run.positions[k, c].tolist() == [float(r[col["x"]]), float(r[col["y"]])]
        assert run.velocities[k, c].tolist() == [float(r[col["vx"]]), float(r[col["vy"]])]
        assert run.angles[k, c] == float(r[col["angle"]])
        assert run.spins[k, c] == float(r[col["omega"]])
    assert (seen == run.present).all()
    assert np.isnan(run.positions[~run.present]).all() and np.isnan(run.spins[~run.present]).all()
    # Bodies came and went: some column is absent in a frame and present in a later one, and
    # some removed body (discharge.csv) is present early and absent at the end.
    assert (~run.present[0]).any() and run.present[-1].sum() < run.present.any(axis=0).sum()
    _, gone = _rows(tmp_path / "discharge.csv")
    gone_ids = [int(g[2]) for g in gone]
    assert gone_ids and not run.present[-1, [ids.index(i) for i in gone_ids]].any()


def test_walls_and_reactions_as_series_match_their_csv_rows(tmp_path):
    # A prescribed paddle turning in a box of disks: reactions.csv and walls.csv both written.
    import numpy as np

    case = dem2d.Case.load(Path(__file__).resolve().parents[2] / "cases" / "paddle_materials.json")
    case = dem2d.Case(dict(json.loads(case.to_json()), duration=0.02, output_every=20))
    dem2d.Simulation(case, out=tmp_path).run()
    run = dem2d.load_run(tmp_path)
    for name, key, series in (("walls.csv", "wall", run.wall_series()),
                              ("reactions.csv", "body", run.reaction_series())):
        header, rows = _rows(tmp_path / name)
        col = {h: k for k, h in enumerate(header)}
        keys = list(dict.fromkeys(int(r[col[key]]) for r in rows))
        steps = list(dict.fromkeys(int(r[col["step"]]) for r in rows))
        assert series[key].tolist() == keys and series["step"].tolist() == steps
        for r in rows:
            k, c = steps.index(int(r[col["step"]])), keys.index(int(r[col[key]]))
            for h in header:
                if h not in ("step", "t", key) and r[col[h]] != "":
                    assert series[h][k, c] == float(r[col[h]]), (name, h)
        assert all(v.shape == (len(steps), len(keys)) for h, v in series.items()
                   if h not in ("step", "t", key))
    assert np.isfinite(run.reaction_series()["fx"]).all()
