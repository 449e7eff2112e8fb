"""The periodic cell's quantities from Python, and energy minimisation (`relax`), against the
command line's files and against what they must be."""

import csv
import json

import numpy as np
import pytest

import dem2d
from conftest import ROOT, cli


def cell_case(shear_rate=3.0, pressure=500.0, n=6, speed=0.5, seed=3):
    """tests/periodic.rs's sheared cell: disks and ellipses on a 1.5 cm lattice in a 9 cm cell,
    periodic in x and y, sheared at imposed pressure."""
    rng = np.random.default_rng(seed)
    bodies = []
    for k in range(n * n):
        i, j = k % n, k // n
        shape = dem2d.circle(0.5) if k % 2 == 0 else dem2d.ellipse(0.7, 0.4)
        bodies.append(
            dem2d.body(
                shape,
                (1.5 * i + 0.7, 1.5 * j + 0.7),
                angle=6.0 * rng.random(),
                velocity=speed * (rng.random(2) - 0.5),
            )
        )
    cell = {"size": [9, 9], "periodic": "xy", "shear_rate": shear_rate}
    if pressure is not None:
        cell["pressure"] = pressure
    return dem2d.Case(
        {
            "version": 1,
            "name": "cell",
            "gravity": [0, 0],
            "dt": 5e-5,
            "duration": 1,
            "output_every": 100,
            "cell": cell,
            "contact": {"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0.4},
            "bodies": bodies,
        }
    )


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_a_sheared_cell_gives_the_command_lines_files_and_its_quantities(tmp_path):
    case = cell_case()
    case.save(tmp_path / "cell.json")
    a, b = tmp_path / "cli", tmp_path / "py"
    cli("run", tmp_path / "cell.json", "--out", a, "--max-steps", 1500, "--quiet", "--analysis")
    sim = dem2d.Simulation(case, out=b, analysis=True, threads=2)
    assert sim.run(1500) == "max_steps"
    for f in ["trajectory.csv", "cell.csv", "analysis.csv", "state.json", "increments.csv"]:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    # The cell now: cell.csv's last row.
    c, last = sim.cell, rows(b / "cell.csv")[-1]
    assert int(last["step"]) == sim.step == 1500
    assert c["periodic"] == "xy" and c["shear_rate"] == 3.0 and c["pressure"] == 500.0
    assert c["size"] == (float(last["lx"]), float(last["ly"]))
    assert (c["offset"], c["shift"]) == (float(last["offset"]), float(last["shift"]))
    s = c["stress"]
    assert [s[0, 0], s[0, 1], s[1, 0], s[1, 1]] == [float(last[k]) for k in ("sxx", "sxy", "syx", "syy")]
    assert c["normal_stress"] == s[1, 1] and c["stiffness_yy"] == float(last["stiffness_yy"])
    assert c["area"] == pytest.approx(c["size"][0] * c["size"][1], rel=1e-15)
    # The shift is the integral of the shear: γ̇ L_y dt summed over the steps (L_y moves with
    # the pressure, so not γ̇ L_y t exactly; bounded by the heights it took).
    ly = np.array([float(r["ly"]) for r in rows(b / "cell.csv")])
    t = sim.time
    assert 3.0 * ly.min() * t * 0.99 < c["shift"] < 3.0 * ly.max() * t * 1.01
    assert c["offset"] == pytest.approx(c["shift"] % c["size"][0], abs=1e-12)
    # The measures of analysis.csv's cell columns.
    m, row = sim.analysis()["cell"], rows(b / "analysis.csv")[-1]
    for k, col in [("pressure", "pressure"), ("shear_stress", "shear_stress"), ("mu_eff", "mu_eff"),
                   ("inertial_number", "inertial_number"), ("ly", "cell_ly")]:
        assert m[k] == float(row[col]), k
    assert m["pressure"] == c["normal_stress"] and m["mu_eff"] == -m["shear_stress"] / m["pressure"]
    # The image counts and the unwrapped positions, read back the same.
    run = dem2d.load_run(b)
    assert run.images.shape == (len(run.step), 36, 2)
    assert np.array_equal(run.images[-1], sim.images)
    assert np.array_equal(run.unwrapped_positions[-1], sim.unwrapped_positions)
    traj = [r for r in rows(b / "trajectory.csv") if int(r["step"]) == 1500]
    assert sim.images.tolist() == [[int(r["ix"]), int(r["iy"])] for r in traj]


def test_unwrapped_positions_follow_the_bodies_through_the_seams():
    # A fast frictionless gas in a cell without shear: the displacement of each step, taken to
    # the nearest image, summed over the steps, is the unwrapped displacement.
    d = cell_case(shear_rate=0.0, pressure=None, speed=400.0).to_dict()
    d["contact"]["friction"] = 0.0
    sim = dem2d.Simulation(dem2d.Case(d), threads=1)
    lx, ly = sim.cell["size"]
    start = sim.unwrapped_positions
    moved = np.zeros_like(start)
    before = sim.positions
    for _ in range(400):
        sim.run(1)
        now = sim.positions
        step = now - before
        step -= np.array([lx, ly]) * np.round(step / np.array([lx, ly]))
        moved += step
        before = now
    assert np.abs(sim.images).max() > 0, "no body crossed a seam"
    assert np.allclose(sim.unwrapped_positions - start, moved, rtol=0, atol=1e-9)
    assert np.all(sim.positions >= 0) and np.all(sim.positions[:, 0] < lx)


def test_no_cell_no_cell_quantities():
    sim = dem2d.Simulation(dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json"))
    assert sim.cell is None and sim.images is None and sim.analysis()["cell"] is None
    assert np.array_equal(sim.unwrapped_positions, sim.positions)


def frictionless_disks():
    """Nine disks dropped into a box, frictionless, under gravity, overlapping a little."""
    bodies = [dem2d.body(dem2d.circle(1.0), (1.0 + 1.9 * (k % 3), 1.0 + 1.9 * (k // 3))) for k in range(9)]
    return dem2d.Case(
        {
            "version": 1,
            "name": "relax",
            "gravity": [0, -980],
            "dt": 1e-5,
            "duration": 0.1,
            "contact": {"model": "linear", "normal_force": "area", "kn_over_rho_g": 36400, "eta_n": 0, "friction": 0},
            "walls": [dem2d.wall((0, 0), (0, 1)), dem2d.wall((0, 0), (1, 0)), dem2d.wall((5.8, 0), (-1, 0))],
            "bodies": bodies,
        }
    )


def test_relax_is_dem2d_relax(tmp_path):
    case = frictionless_disks()
    case.save(tmp_path / "case.json")
    cli("relax", tmp_path / "case.json", "--out", tmp_path / "cli", "--quiet")
    sim = dem2d.Simulation(case, threads=2)
    r = sim.relax()
    assert r["status"] == "relaxed" and r["converged"] and r["residual"] < 1e-9
    summary = json.loads((tmp_path / "cli" / "relax.json").read_text())
    assert (r["iterations"], r["residual"], r["potential"]) == (
        summary["iterations"], summary["residual"], summary["potential"]
    )
    state = json.loads((tmp_path / "cli" / "state.json").read_text())
    assert sim.positions.tolist() == [b["position"] for b in state["bodies"]]
    # At rest: every body's force (contacts and gravity) balances to the tolerance's order.
    weight = sim.masses * 980
    assert np.all(np.linalg.norm(sim.forces, axis=1) < 1e-6 * weight)
    assert sim.step == 0 and np.all(sim.velocities == 0)
    # A run from there stays put.
    sim.run(100)
    assert np.abs(sim.velocities).max() < 1e-6


def test_relax_refuses_friction_with_the_command_lines_message(tmp_path):
    path = ROOT / "cases" / "settle3_dt1e-5.json"
    with pytest.raises(dem2d.InputError) as e:
        dem2d.Simulation(dem2d.Case.load(path)).relax()
    assert e.value.field == "contact.friction"
    code, _, err = cli("relax", path, "--out", tmp_path / "never", check=False)
    assert code == 2 and err.strip() == f"dem2d: {e.value}"
    with pytest.raises(dem2d.InputError, match="tolerance: must be a positive number"):
        dem2d.Simulation(frictionless_disks()).relax(tolerance=0)


def test_each_sides_control_and_the_width_that_follows_it():
    # `cell.stress` and `cell.strain_rate` (the command line's keys) in `sim.cell`: the width
    # follows σ_xx, the height is strained at its rate: L_y = 9 exp(ε̇ t) to round-off.
    case = cell_case(shear_rate=0.0, pressure=None)
    bodies = json.loads(case.to_json())["bodies"]
    spec = {
        "version": 1, "name": "cell", "gravity": [0, 0], "dt": 5e-5, "duration": 1,
        "output_every": 100,
        "cell": {"size": [9, 9], "periodic": "xy", "stress": {"xx": 500},
                 "strain_rate": {"yy": -0.2}},
        "contact": {"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0.4},
        "bodies": bodies,
    }
    sim = dem2d.Simulation(dem2d.Case(spec), threads=1)
    sim.run(2000)
    c = sim.cell
    assert c["stress_xx"] == 500 and c["stress_yy"] is None
    assert c["strain_rate_yy"] == -0.2 and c["strain_rate_xx"] is None
    want = 9 * np.exp(-0.2 * 2000 * 5e-5)
    assert abs(c["size"][1] - want) < 1e-12 * want
    # The grains on a 1.5 cm lattice touch nothing at first: the width shrinks at the cap.
    assert c["size"][0] < 9
    with pytest.raises(dem2d.InputError, match="cell.strain_rate.yy"):
        spec["cell"]["strain_rate"] = {"yy": -1e5}
        dem2d.Case(spec)
