"""`dem2d.export` (the LAMMPS-style dump for OVITO) and `dem2d.animate` (the HTML player) from
Python: the same bytes as `dem2d export` and `dem2d animate`, the dump written while a
Simulation runs (`dump=True`) equal to the export of its run, the dump's rows against the run
read back, and the errors."""

import base64
import json
import math

import numpy as np
import pytest

import dem2d
from conftest import ROOT, case_dict, cli


def settle3(tmp_path):
    """P's three ellipses on a floor, 0.05 s, run from Python with the dump on."""
    case = dem2d.Case.load(ROOT / "cases" / "settle3_dt1e-5.json")
    d = case.to_dict()
    d["duration"] = 0.05
    d["output_every"] = 1000
    out = tmp_path / "py"
    with dem2d.Simulation(dem2d.Case(d), threads=1, out=out, dump=True) as sim:
        sim.run()
    return out


def test_the_dump_of_a_python_run_is_the_export_of_it_and_holds_its_frames(tmp_path):
    out = settle3(tmp_path)
    written = (out / "dump.lammpstrj").read_bytes()
    p = dem2d.export(out, out=tmp_path / "py.lammpstrj")
    assert p == tmp_path / "py.lammpstrj"
    assert p.read_bytes() == written
    cli("export", out, "--format", "lammps-dump", "--out", tmp_path / "cli.lammpstrj")
    assert (tmp_path / "cli.lammpstrj").read_bytes() == written
    # The default place, through the Run.
    run = dem2d.load_run(out)
    assert run.export() == out / "dump.lammpstrj"
    assert (out / "dump.lammpstrj").read_bytes() == written

    # Each frame's atoms against the run read back: positions to the bit, the quaternion's
    # angle the body's (mod 2π), the ellipses' diameters.
    text = written.decode().split("\n")
    k, frame = 0, 0
    axes = [(b["shape"]["a"], b["shape"]["b"]) for b in run.case.to_dict()["bodies"]]
    while k < len(text) - 1:
        assert text[k] == "ITEM: TIME" and text[k + 2] == "ITEM: TIMESTEP"
        assert int(text[k + 3]) == run.step[frame]
        n = int(text[k + 5])
        assert text[k + 10].startswith("ITEM: ATOMS id type x y z vx vy omegaz shapex shapey")
        rows = np.array([[float(v) for v in line.split()] for line in text[k + 11 : k + 11 + n]])
        assert np.array_equal(rows[:, 0], np.arange(1, n + 1))
        assert np.array_equal(rows[:, 2:4], run.positions[frame])
        turn = 2 * np.arctan2(rows[:, 14], rows[:, 11]) - run.angles[frame]
        assert np.abs(turn - 2 * math.pi * np.round(turn / (2 * math.pi))).max() < 1e-12
        assert np.allclose(rows[:, 8:10], 2 * np.array(axes), rtol=1e-15, atol=0)
        k += 11 + n
        frame += 1
    assert frame == len(run.step) == 6


def test_animate_from_python_is_the_command_lines_player(tmp_path):
    out = settle3(tmp_path)
    p = dem2d.load_run(out).animate()
    assert p == out / "animation.html"
    html = p.read_text(encoding="utf-8")
    cli("animate", out, "--out", tmp_path / "cli.html")
    assert (tmp_path / "cli.html").read_text(encoding="utf-8") == html
    assert "default-src 'none'" in html and "https:" not in html
    start = html.index('<script id="data" type="application/json">') + 42
    data = json.loads(html[start : html.index("</script>", start)])
    assert len(data["frames"]) == 6
    # The first frame's positions, as 32-bit floats.
    state = np.frombuffer(base64.b64decode(data["state"]), dtype="<f4").reshape(-1, 6)
    run = dem2d.load_run(out)
    assert np.array_equal(state[:3, :2], run.positions[0].astype(np.float32))
    thin = dem2d.animate(out, tmp_path / "thin.html", every=4)
    start = thin.read_text().index('<script id="data" type="application/json">') + 42
    data = json.loads(thin.read_text()[start : thin.read_text().index("</script>", start)])
    assert [f["step"] for f in data["frames"]] == [0, 4000, 5000]


def test_bad_requests_raise_input_errors(tmp_path, monkeypatch):
    out = settle3(tmp_path)
    with pytest.raises(dem2d.InputError, match="lammps-dump"):
        dem2d.export(out, format="vtk")
    with pytest.raises(dem2d.InputError, match="case.json"):
        dem2d.export(tmp_path / "nothing")
    with pytest.raises(dem2d.InputError, match=r"\.html"):
        dem2d.animate(out, tmp_path / "x.svg")
    with pytest.raises(dem2d.InputError, match="every"):
        dem2d.animate(out, every=0)
    with pytest.raises(dem2d.OutputError, match="cannot write"):
        dem2d.export(out, out=tmp_path / "no" / "such" / "d.lammpstrj")
    # A movie without ffmpeg says so (PATH without it).
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(dem2d.InputError, match="ffmpeg not found"):
        dem2d.animate(out, tmp_path / "m.gif")


def test_fields_are_the_command_lines(tmp_path):
    # `Run.fields` writes the bytes `dem2d fields` writes and returns its columns; a run without
    # contacts.csv warns, a bad option raises InputError naming it.
    d = case_dict("shear_cell.json")
    d["duration"] = 0.2
    (tmp_path / "case.json").write_text(json.dumps(d))
    cli("run", tmp_path / "case.json", "--out", tmp_path / "run", "--contacts", "--quiet")
    cli("fields", tmp_path / "run", "--bins", "5", "--out", tmp_path / "cli.csv")
    run = dem2d.load_run(tmp_path / "run")
    f = run.fields(bins=5)
    assert (tmp_path / "run" / "fields.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert len(f["y"]) == 5 and f["syy"].mean() > 0
    with pytest.raises(dem2d.InputError, match="--bins"):
        run.fields(bins=0)
    with pytest.raises(dem2d.InputError, match="axis"):
        run.fields(axis="z", bins=3)
    cli("run", tmp_path / "case.json", "--out", tmp_path / "bare", "--quiet", "--max-steps", "800")
    with pytest.warns(UserWarning, match="contacts.csv"):
        g = dem2d.load_run(tmp_path / "bare").fields(bins=3)
    assert all(v != v for v in g["sxx"])


def test_forces_are_the_command_lines(tmp_path):
    # `Run.forces` writes what `dem2d forces` writes and returns forces.json with the histogram.
    d = case_dict("shear_cell.json")
    d["duration"] = 0.2
    (tmp_path / "case.json").write_text(json.dumps(d))
    cli("run", tmp_path / "case.json", "--out", tmp_path / "run", "--contacts", "--quiet")
    cli("forces", tmp_path / "run", "--from", "0.1")
    want = (tmp_path / "run" / "forces.csv").read_bytes()
    r = dem2d.load_run(tmp_path / "run").forces(start=0.1)
    assert (tmp_path / "run" / "forces.csv").read_bytes() == want
    width = 2 * r["distribution"]["f_over_mean"][0]
    assert abs((r["distribution"]["pdf"] * width).sum() - 1) < 1e-12
    assert r["contacts"] == int(r["distribution"]["count"].sum())
    with pytest.raises(dem2d.InputError, match="--frame"):
        dem2d.load_run(tmp_path / "run").forces(frame=10**6)
