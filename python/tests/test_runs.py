"""A case run from Python against the same case run by `dem2d run`: the same files, bit for bit;
the arrays against the files the run wrote; reading a run directory back."""

import csv
import json

import numpy as np
import pytest

import dem2d
from conftest import ROOT, case_dict, cli

# The files of a run that hold no wall time (summary.json does: compared without it).
SAME_BYTES = ["trajectory.csv", "increments.csv", "state.json", "case.json"]


def summary_without_clock(path):
    s = json.loads((path / "summary.json").read_text())
    for k in ("wall_seconds", "particle_steps_per_second"):
        s.pop(k)
    return s


def short(name, **changes):
    """A shipped case with some keys changed, as a Case and as a file beside it."""
    d = case_dict(name)
    d.update(changes)
    return dem2d.Case(d)


CASES = [
    # The README's case: three ellipses on a floor between walls, to rest.
    ("settle3", lambda: dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json"), {}),
    # Moving servo walls and 400 disks, 2000 steps.
    ("biaxial", lambda: dem2d.Case.load(ROOT / "cases" / "biaxial_disks.json"), {"steps": 2000}),
    # A clump and a polygon dropped on a floor, through their first bounce.
    ("clump", lambda: short("drop_rebound_clump9.json", duration=0.08), {}),
    ("polygon", lambda: short("drop_rebound_polygon64.json", duration=0.08), {}),
]


@pytest.mark.parametrize("name,make,how", CASES, ids=[c[0] for c in CASES])
def test_python_run_gives_the_command_lines_files_bit_for_bit(tmp_path, name, make, how):
    case = make()
    file = case.source or tmp_path / f"{name}.json"
    if case.source is None:
        case.save(file)
    a, b = tmp_path / "cli", tmp_path / "py"
    args = ["run", file, "--out", a, "--quiet", "--threads", "1", "--contacts", "--analysis"]
    if "steps" in how:
        args += ["--max-steps", how["steps"]]
    cli(*args)
    sim = dem2d.Simulation(case, threads=2, out=b, contacts=True, analysis=True)
    status = sim.run(how["steps"]) if "steps" in how else sim.run()
    assert status == json.loads((a / "summary.json").read_text())["status"]
    for f in SAME_BYTES + ["contacts.csv", "analysis.csv"] + (["walls.csv"] if case.n_walls else []):
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    assert summary_without_clock(a) == summary_without_clock(b)


def test_a_run_in_parts_gives_the_whole_runs_files(tmp_path):
    # Parts of 1000 steps end on output frames (output_every 100): the same rows as one run.
    path = ROOT / "cases" / "settle3_dt1e-4.json"
    a, b = tmp_path / "cli", tmp_path / "py"
    cli("run", path, "--out", a, "--quiet")
    case = dem2d.Case.load(path)
    sim = dem2d.Simulation(case, out=b)
    status = None
    while sim.step + 1000 < case.steps and status != "at_rest":
        status = sim.run(1000)
    if status != "at_rest":
        status = sim.run()
    assert status == json.loads((a / "summary.json").read_text())["status"]
    for f in SAME_BYTES:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_arrays_are_the_files_numbers(tmp_path):
    case = dem2d.Case.load(ROOT / "cases" / "biaxial_disks.json")
    sim = dem2d.Simulation(case, out=tmp_path, contacts=True, analysis=True)
    assert sim.run(300) == "max_steps"
    step = sim.step
    # The trajectory's last frame: the state now.
    last = [r for r in rows(tmp_path / "trajectory.csv") if int(r["step"]) == step]
    assert len(last) == sim.n_bodies == 400
    col = lambda rs, k: np.array([float(r[k]) for r in rs])  # noqa: E731
    assert np.array_equal(sim.positions, np.stack([col(last, "x"), col(last, "y")], axis=1))
    assert np.array_equal(sim.angles, col(last, "angle"))
    assert np.array_equal(sim.velocities, np.stack([col(last, "vx"), col(last, "vy")], axis=1))
    assert np.array_equal(sim.spins, col(last, "omega"))
    # The contacts of the last frame, row for row.
    c = sim.contacts()
    lc = [r for r in rows(tmp_path / "contacts.csv") if int(r["step"]) == step]
    assert len(lc) == len(c["j"]) > 400
    giver = [r["i"] for r in lc]
    assert [str(i) if i >= 0 else f"w{w}" for i, w in zip(c["i"], c["wall"])] == giver
    assert np.array_equal(c["j"], [int(r["j"]) for r in lc])
    for k, (x, y) in {"point": ("px", "py"), "normal": ("nx", "ny")}.items():
        assert np.array_equal(c[k], np.stack([col(lc, x), col(lc, y)], axis=1)), k
    for k in ("fn", "ft", "couple", "depth"):
        assert np.array_equal(c[k], col(lc, k)), k
    assert c["state"] == [r["state"] for r in lc]
    # The force on j is fn n + ft t, t = (-n_y, n_x).
    n, f = c["normal"], c["force"]
    assert np.allclose(np.einsum("ij,ij->i", f, n), c["fn"], rtol=1e-12, atol=1e-9)
    # The measures of the last analysis row.
    a = sim.analysis()
    row = rows(tmp_path / "analysis.csv")[-1]
    assert float(row["t"]) == sim.time
    assert a["packing_fraction"] == float(row["packing_fraction"])
    assert a["coordination"] == float(row["z"])
    s = a["stress"]
    assert (s[0, 0], s[1, 1], s[0, 1], s[1, 0]) == tuple(
        float(row[k]) for k in ("sxx", "syy", "sxy", "sxy")
    )
    assert a["contacts"] == int(row["contacts"]) == len(c["j"])
    assert a["fabric"]["a_c"] == float(row["a_c"])
    # And the forces: each body's is the sum of its contacts' and gravity (the same numbers
    # summed another way: not bit for bit).
    forces = np.zeros_like(sim.positions)
    forces += sim.masses[:, None] * np.array(case.gravity)
    np.add.at(forces, c["j"], f)
    bodies = c["i"] >= 0
    np.add.at(forces, c["i"][bodies], -f[bodies])
    scale = np.abs(f).max()
    assert np.allclose(sim.forces, forces, rtol=0, atol=1e-9 * scale)


def test_a_run_directory_reads_back_as_the_files_say(tmp_path):
    case = dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json")
    sim = dem2d.Simulation(case, out=tmp_path, contacts=True, analysis=True)
    sim.run(2000)
    run = dem2d.load_run(tmp_path)
    traj = rows(tmp_path / "trajectory.csv")
    steps = sorted({int(r["step"]) for r in traj})
    assert list(run.step) == steps == list(range(0, 2001, 100))
    assert run.positions.shape == (len(steps), 3, 2)
    for r in traj:
        k, b = steps.index(int(r["step"])), int(r["body"])
        assert run.positions[k, b].tolist() == [float(r["x"]), float(r["y"])]
        assert run.angles[k, b] == float(r["angle"])
        assert run.velocities[k, b].tolist() == [float(r["vx"]), float(r["vy"])]
        assert run.spins[k, b] == float(r["omega"])
    assert np.array_equal(run.positions[-1], sim.positions)
    assert run.status == "max_steps" and run.summary["steps"] == 2000
    inc = rows(tmp_path / "increments.csv")
    assert np.array_equal(run.increments["mean_dx"], [float(r["mean_dx"]) for r in inc])
    assert list(run.contacts["step"]) == [int(r["step"]) for r in rows(tmp_path / "contacts.csv")]
    assert np.array_equal(run.contacts["fn"], sim_contacts_of_file(tmp_path)["fn"])
    assert run.analysis["packing_fraction"][-1] == sim.analysis()["packing_fraction"]
    assert run.walls is not None and len(run.walls["wall"]) == 3 * len(steps)
    # The state file continues the run: the same as running on.
    cont = dem2d.Simulation(run.state)
    assert cont.step == 2000
    cont.run(500)
    sim.run(500)
    assert np.array_equal(cont.positions, sim.positions)
    assert np.array_equal(cont.spins, sim.spins)


def sim_contacts_of_file(path):
    return {"fn": np.array([float(r["fn"]) for r in rows(path / "contacts.csv")])}


def test_results_do_not_depend_on_the_threads():
    case = dem2d.Case.load(ROOT / "cases" / "biaxial_disks.json")
    one, four = dem2d.Simulation(case, threads=1), dem2d.Simulation(case, threads=4)
    assert (one.threads, four.threads) == (1, 4)
    one.run(500)
    four.run(500)
    assert np.array_equal(one.positions, four.positions)
    assert np.array_equal(one.forces, four.forces)


def test_duration_and_until_rest(tmp_path):
    case = dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json")
    sim = dem2d.Simulation(case)
    assert sim.run(duration=0.001) == "completed" and sim.step == 100
    assert sim.run(until_rest=True) == "at_rest"
    # At rest: the mean increments of the step are below the case's criterion.
    rest = sim.step
    assert rest < case.steps
    assert sim.run(50, until_rest=False) == "max_steps" and sim.step == rest + 50
    no_rest = dict(case.to_dict())
    del no_rest["quiescence"]
    with pytest.raises(dem2d.InputError, match="until_rest: the case has no `quiescence`"):
        dem2d.Simulation(dem2d.Case(no_rest)).run(until_rest=True)


def test_the_tutorial_script_runs(tmp_path):
    # docs/python/pour.py, small and short: it builds its scene, runs, prints the profile.
    import subprocess
    import sys

    p = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "python" / "pour.py"), "--n", "40", "--width", "30",
         "--steps", "2000", "--threads", "1", "--out", str(tmp_path / "pour")],
        capture_output=True, text=True, timeout=300,
    )
    assert p.returncode == 0, p.stderr
    assert "40 ellipses: max_steps at t = 0.0200 s (step 2000)" in p.stdout
    assert "depth (cm)  packing fraction" in p.stdout
    assert dem2d.load_run(tmp_path / "pour").step[-1] == 2000


def test_vtk_frames_are_the_command_lines(tmp_path):
    path = ROOT / "cases" / "settle3_dt1e-4.json"
    a, b = tmp_path / "cli", tmp_path / "py"
    cli("run", path, "--out", a, "--quiet", "--vtk-every", "500")
    with dem2d.Simulation(dem2d.Case.load(path), out=b, vtk=500) as sim:
        sim.run()
    frames = sorted(p.name for p in (a / "vtk").iterdir())
    assert len(frames) > 2 and frames == sorted(p.name for p in (b / "vtk").iterdir())
    for f in ["run.pvd"] + [f"vtk/{n}" for n in frames]:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    # Closed: the directory is free for another run, this simulation refuses to go on.
    assert not (b / ".dem2d.lock").exists()
    with pytest.raises(dem2d.RunError, match="was closed"):
        sim.run(10)
    dem2d.Simulation(dem2d.Case.load(path), out=b, overwrite=True).run(10)


def test_a_killed_python_run_leaves_its_last_checkpoint(tmp_path):
    # `checkpoint_every=N` as `dem2d run --checkpoint-every N`: a Python process killed outright
    # (SIGKILL, nothing written at the end) leaves the state of a step that is a multiple of N,
    # with the status `checkpoint`, and the command line continues it.
    import subprocess
    import sys
    import time

    case = dem2d.Case(case_dict("settle3_dt1e-5.json"))
    with pytest.raises(dem2d.InputError, match="checkpoint_every"):
        dem2d.Simulation(case, checkpoint_every=0)
    d = case_dict("settle3_dt1e-5.json")
    d["duration"] = 1e3
    d.pop("quiescence")  # (it comes to rest in 881 steps)
    (tmp_path / "case.json").write_text(json.dumps(d))
    out = tmp_path / "py"
    script = tmp_path / "run.py"
    script.write_text(
        "import dem2d\n"
        f"case = dem2d.Case.load({str(tmp_path / 'case.json')!r})\n"
        f"with dem2d.Simulation(case, threads=1, out={str(out)!r}, checkpoint_every=1000) as sim:\n"
        "    sim.run(10**9)\n"
    )
    child = subprocess.Popen([sys.executable, str(script)])
    state, deadline = None, time.time() + 120
    try:
        while time.time() < deadline and child.poll() is None:
            try:
                s = json.loads((out / "state.json").read_text())
                if s["state"]["step"] >= 2000:
                    state = s
                    break
            except (OSError, ValueError):
                pass  # not there yet (it is replaced atomically, never torn)
            time.sleep(0.02)
    finally:
        child.kill()
        child.wait()
    assert state is not None, "no checkpoint past step 2000 within two minutes"
    state = json.loads((out / "state.json").read_text())
    assert state["state"]["status"] == "checkpoint"
    assert state["state"]["step"] % 1000 == 0 and state["state"]["step"] >= 2000
    cli("run", out / "state.json", "--out", tmp_path / "on", "--max-steps", "500", "--quiet")
