"""Pouring from Python: a case built with `insert` and `outflow` runs as the command line runs
it, inserts ⌊rate · t⌋ bodies and logs each removed body once."""

import math

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
