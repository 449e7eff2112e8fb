"""Issue 41 from Python: what the command line now refuses or warns of, Python refuses or warns
of too, with dem2d's own exceptions (never a PanicException, an OverflowError or silence)."""

import json

import pytest

import dem2d
from conftest import case_dict, cli
from test_flow import falling_case


def test_vtk_on_a_run_that_inserts_bodies_writes_the_command_lines_frames(tmp_path):
    # It panicked at the first inserted body (PanicException): the outlines were kept by index.
    case = dem2d.Case(falling_case())
    sim = dem2d.Simulation(case, threads=1, out=tmp_path / "py", vtk=500)
    assert sim.run() == "completed"
    case.save(tmp_path / "case.json")
    cli("run", tmp_path / "case.json", "--out", tmp_path / "cli", "--vtk-every", "500",
        "--threads", "1", "--quiet")
    frames = sorted(p.name for p in (tmp_path / "cli" / "vtk").iterdir())
    assert len(frames) == 4  # steps 0, 500, 1000 and the last, 1500
    for f in frames:
        assert (tmp_path / "py" / "vtk" / f).read_bytes() == (tmp_path / "cli" / "vtk" / f).read_bytes()


def test_threads_beyond_four_per_core_and_negative_counts_are_input_errors():
    case = dem2d.Case(case_dict("settle3_dt1e-5.json"))
    with pytest.raises(dem2d.InputError, match=r"threads: .* at most \d+ accepted"):
        dem2d.Simulation(case, threads=10**6)
    with pytest.raises(dem2d.InputError, match=r"threads: must be a whole number ≥ 1, got -1"):
        dem2d.Simulation(case, threads=-1)
    with pytest.raises(dem2d.InputError, match=r"threads: must be a whole number ≥ 1, got 2.5"):
        dem2d.Simulation(case, threads=2.5)


def test_a_negative_step_count_is_an_input_error_not_an_overflow():
    sim = dem2d.Simulation(dem2d.Case(case_dict("settle3_dt1e-5.json")), threads=1)
    for bad, shown in ((-5, "-5"), (2.5, "2.5"), ("10", "'10'"), (True, "True"), (2**70, str(2**70))):
        with pytest.raises(dem2d.InputError, match=f"steps: must be a whole number ≥ 1, got {shown}"):
            sim.run(bad)
    with pytest.raises(dem2d.InputError, match="steps: must be at least 1"):
        sim.run(0)
    assert sim.run(3) == "max_steps" and sim.step == 3


def test_python_sees_the_command_lines_warnings(tmp_path):
    # Δt above the a-priori critical step, and gravity in m/s²: Case.warnings and a Python
    # warning (UserWarning) when a simulation is made, the same texts as summary.json's.
    for key, value, said in (("dt", 1e-3, "exceeds the critical time step"),
                             ("gravity", [0, -9.81], "is Earth's in m/s²")):
        d = case_dict("settle3_dt1e-5.json")
        d[key] = value
        case = dem2d.Case(d)
        assert [w for w in case.warnings if said in w], case.warnings
        with pytest.warns(UserWarning, match=said):
            dem2d.Simulation(case, threads=1)
        case.save(tmp_path / f"{key}.json")
        cli("run", tmp_path / f"{key}.json", "--out", tmp_path / key, "--max-steps", "1", "--quiet")
        summary = json.loads((tmp_path / key / "summary.json").read_text())
        for w in case.warnings:
            assert w in summary["warnings"]


def test_a_scene_filled_by_insertion_is_warned_of_a_coarse_step():
    d = falling_case()
    d["dt"] = 1e-2
    assert any("exceeds the critical time step" in w for w in dem2d.Case(d).warnings)


def test_units_other_than_cm_are_refused_naming_the_field():
    d = case_dict("settle3_dt1e-5.json")
    d["units"] = "m"
    with pytest.raises(dem2d.InputError, match='may only be "cm"') as e:
        dem2d.Case(d)
    assert e.value.field == "units"
