"""Scenes from Python: the case file's keys from a dict, the JSON written back, and bad input
refused with the command line's messages, naming the field."""

import json
import math

import numpy as np
import pytest

import dem2d
from conftest import ROOT, case_dict, cli

BAD = ROOT / "cases" / "bad"
EXPECTED = json.loads((BAD / "expected_errors.json").read_text(encoding="utf-8"))


def case_files():
    """Every shipped case file (not the bad ones, not the `dem2d contact` input)."""
    return [
        p
        for p in sorted((ROOT / "cases").rglob("*.json"))
        if p.parent.name != "bad" and p.name != "contacts_demo.json"
    ]


def test_a_file_is_written_back_byte_for_byte(tmp_path):
    for path in case_files():
        case = dem2d.Case.load(path)
        assert case.to_json() == path.read_text(encoding="utf-8")
        case.save(tmp_path / "again.json")
        assert (tmp_path / "again.json").read_bytes() == path.read_bytes()


def floats(v):
    """Every float of a JSON value, in order, as bits."""
    if isinstance(v, dict):
        return [x for k in v for x in floats(v[k])]
    if isinstance(v, list):
        return [x for i in v for x in floats(i)]
    if isinstance(v, float):
        return [v.hex()]
    return []


def test_a_dict_survives_the_round_trip_bit_for_bit():
    d = case_dict("settle3_dt1e-5.json")
    # Numbers whose shortest decimal forms are long, a subnormal-free tiny one and numpy values.
    d["bodies"][2]["position"] = [0.1 + 0.2, 2.80299164330017 + 1e-15]
    d["bodies"][2]["angle"] = math.pi / 7
    d["bodies"][0]["velocity"] = np.array([1 / 3, -2 / 3])
    d["bodies"][1]["omega"] = np.float64(1e-300)
    case = dem2d.Case(d)
    back = case.to_dict()
    plain = json.loads(json.dumps(d, default=lambda o: o.tolist()))
    assert back == plain
    assert floats(back) == floats(plain)
    again = dem2d.Case(back)
    assert again.to_json() == case.to_json() and again == case
    # The keys keep the dict's order.
    assert list(back) == list(d)


def test_every_case_key_is_read_from_a_dict():
    # Each shipped case, as a dict, gives the same case as its file (every key the shipped
    # cases use: walls with servos and velocities, clumps, polygons, rolling resistance, Hertz).
    for path in case_files():
        d = json.loads(path.read_text(encoding="utf-8"))
        a, b = dem2d.Case.load(path), dem2d.Case(d)
        assert (a.name, a.dt, a.duration, a.n_bodies, a.n_walls, a.gravity) == (
            b.name,
            b.dt,
            b.duration,
            b.n_bodies,
            b.n_walls,
            b.gravity,
        )
        sa, sb = dem2d.Simulation(a), dem2d.Simulation(b)
        assert np.array_equal(sa.positions, sb.positions)
        assert np.array_equal(sa.forces, sb.forces), path


def test_helpers_build_the_case_files_forms():
    case = dem2d.Case(
        {
            "version": 1,
            "name": "helpers",
            "gravity": [0, -980],
            "dt": 1e-5,
            "duration": 0.01,
            "contact": {"model": "linear", "kn": 1e7, "eta_n": 10, "friction": 0.3},
            "walls": [dem2d.wall((0, 0), (0, 1), friction=0.5)],
            "bodies": [
                dem2d.body(dem2d.circle(1), (0, 1.5)),
                dem2d.body(dem2d.ellipse(1.5, 1), (4, 2), angle=0.3, velocity=(1, 0)),
                dem2d.body(dem2d.rectangle(2, 1), (8, 2), omega=1.0, density=2.0),
                dem2d.body(dem2d.polygon([(0, 0), (2, 0), (1, 1.5)]), (12, 2)),
                dem2d.body(dem2d.clump([(-0.5, 0, 0.6), (0.5, 0, 0.6)]), (16, 2)),
            ],
        }
    )
    sim = dem2d.Simulation(case)
    s = sim.shapes()
    assert s["type"] == ["circle", "ellipse", "rectangle", "polygon", "clump"]
    assert s["r"][0] == 1 and (s["a"][1], s["b"][1]) == (1.5, 1) and (s["w"][2], s["h"][2]) == (2, 1)
    assert np.isnan(s["r"][1:]).all()
    assert s["vertices"][3].shape == (3, 2) and s["disks"][4].shape == (2, 3)
    # Closed forms: the areas and the polygon's centroid (its vertices are about it).
    assert np.allclose(s["area"][:4], [math.pi, math.pi * 1.5, 2, 1.5], rtol=1e-14)
    assert np.allclose(s["vertices"][3].mean(axis=0), 0, atol=1e-15)
    assert np.allclose(sim.masses[2], 4.0)
    assert sim.angles[1] == 0.3 and sim.velocities[1].tolist() == [1, 0] and sim.spins[2] == 1


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bad_files_are_refused_with_the_command_lines_message(name):
    path = BAD / name
    with pytest.raises(dem2d.InputError) as e:
        dem2d.Case.load(path)
    assert EXPECTED[name] in str(e.value)
    assert str(e.value).startswith(f"{path}: ")
    field = EXPECTED[name].removeprefix("field `").split("`")[0]
    if EXPECTED[name].startswith("field `"):
        assert e.value.field == field
    assert isinstance(e.value, ValueError)


def test_messages_are_the_command_lines():
    # The same text as `dem2d run` prints after `dem2d: `.
    for name in ["negative_size.json", "misspelled_key.json", "nan.json", "state_time.json"]:
        path = BAD / name
        code, _, err = cli("run", path, "--out", "/nonexistent/never", check=False)
        assert code == 2
        with pytest.raises(dem2d.InputError) as e:
            dem2d.Case.load(path)
        assert err.strip() == f"dem2d: {e.value}"


def test_a_dict_is_refused_naming_the_field():
    d = case_dict("settle3_dt1e-5.json")
    d["bodies"][1]["shape"]["a"] = -1.0
    with pytest.raises(dem2d.InputError, match=r"^field `bodies\[1\].shape.a`: must be positive") as e:
        dem2d.Case(d)
    assert e.value.field == "bodies[1].shape.a"
    d = case_dict("settle3_dt1e-5.json")
    d["contact"]["frcition"] = 0.3
    with pytest.raises(dem2d.InputError, match="frcition") as e:
        dem2d.Case(d)
    assert e.value.field == "contact.frcition"
    assert "friction" in str(e.value)
    d = case_dict("settle3_dt1e-5.json")
    d["gravity"] = [0, float("nan")]
    with pytest.raises(dem2d.InputError, match="must be a finite number, got NaN") as e:
        dem2d.Case(d)
    assert e.value.field == "gravity[1]"
    with pytest.raises(dem2d.InputError, match="a case is a dict"):
        dem2d.Case("cases/settle3_dt1e-5.json")
    with pytest.raises(TypeError, match="not a case value"):
        dem2d.Case({"version": 1, "name": object()})


def test_bad_arguments_name_the_argument(tmp_path):
    case = dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json")
    with pytest.raises(dem2d.InputError, match="threads: must be at least 1"):
        dem2d.Simulation(case, threads=0)
    sim = dem2d.Simulation(case)
    with pytest.raises(dem2d.InputError, match="steps: must be at least 1"):
        sim.run(0)
    with pytest.raises(dem2d.InputError, match="give steps or duration, not both"):
        sim.run(10, duration=0.1)
    with pytest.raises(dem2d.InputError, match="duration: must be a positive time"):
        sim.run(duration=-1.0)
    # An occupied directory: the command line's message.
    dem2d.Simulation(case, out=tmp_path).run(10)
    with pytest.raises(dem2d.InputError, match="holds the outputs of an earlier run") as e:
        dem2d.Simulation(case, out=tmp_path)
    code, _, err = cli("run", case.source, "--out", tmp_path, check=False)
    assert code == 2 and err.strip() == f"dem2d: {e.value}"
    dem2d.Simulation(case, out=tmp_path, overwrite=True)
