"""Stopping a run: from another thread, by Ctrl-C, by a blow-up; the GIL released while it steps."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import dem2d
from conftest import ROOT, case_dict, cli


def long_case():
    """The biaxial test's 400 disks, run far longer than a test waits (5e5 steps)."""
    d = case_dict("biaxial_disks.json")
    d["duration"] = 5.0
    return dem2d.Case(d)


def test_a_run_in_a_background_thread_is_interrupted(tmp_path):
    sim = dem2d.Simulation(long_case(), threads=1, out=tmp_path)
    result = {}
    thread = threading.Thread(target=lambda: result.setdefault("status", sim.run()))
    thread.start()
    # The run holds the simulation: reading it meanwhile is refused, not blocked.
    time.sleep(0.5)
    with pytest.raises(dem2d.RunError, match="the simulation is running"):
        sim.positions
    sim.interrupt()
    thread.join(timeout=60)
    assert not thread.is_alive()
    assert result["status"] == "interrupted"
    steps = sim.step
    assert 0 < steps < 500_000
    s = json.loads((tmp_path / "summary.json").read_text())
    assert (s["status"], s["steps"]) == ("interrupted", steps)
    assert f"after step {steps}" in s["error"]
    # The state saved continues the run, as the command line's would.
    run = dem2d.load_run(tmp_path)
    assert run.step[-1] == steps and np.array_equal(run.positions[-1], sim.positions)
    assert run.state.state_step == steps


def test_the_gil_is_released_while_stepping():
    sim = dem2d.Simulation(long_case(), threads=1)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    sim.run(30_000)
    end = time.perf_counter()
    stop.set()
    counter.join()
    during = [t for t in ticks if start < t < end]
    # Python ran all along: a held GIL would leave one gap as long as the run; the margin is
    # for a loaded machine's scheduling.
    assert end - start > 0.2, "the run was too short to tell"
    gaps = np.diff([start, *during, end])
    assert gaps.max() < 0.3 * (end - start), (gaps.max(), end - start)
    assert len(during) > 10


# The child restores Python's own Ctrl-C handler: a process started with SIGINT ignored (a
# background job of a non-interactive shell, as a CI runner may start the tests) inherits that,
# and Python then installs no handler, so no Ctrl-C could reach it.
CTRL_C = textwrap.dedent(
    """
    import signal, sys, dem2d
    signal.signal(signal.SIGINT, signal.default_int_handler)
    sys.path.insert(0, {tests!r})
    from test_control import long_case
    sim = dem2d.Simulation(long_case(), threads=1, out={out!r})
    print("running", flush=True)
    try:
        sim.run()
    except KeyboardInterrupt:
        print("KeyboardInterrupt at step", sim.step, flush=True)
        sys.exit(3)
    print("not interrupted", flush=True)
    """
)


def test_ctrl_c_stops_a_run_cleanly(tmp_path):
    out = tmp_path / "out"
    script = CTRL_C.format(tests=str(ROOT / "python" / "tests"), out=str(out))
    p = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert p.stdout.readline().strip() == "running"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == 3, stderr
    steps = int(stdout.split("KeyboardInterrupt at step")[1])
    assert steps > 0
    s = json.loads((out / "summary.json").read_text())
    assert (s["status"], s["steps"]) == ("interrupted", steps)
    assert s["error"] == f"interrupted by signal 2 (SIGINT) after step {steps}"
    # The files are whole: the command line continues from the state.
    rows = (out / "trajectory.csv").read_text().splitlines()
    assert rows[-1].startswith(f"{steps},")
    cli("run", out / "state.json", "--out", tmp_path / "more", "--max-steps", "10", "--quiet")


BLOWUP = {
    # tests/cases.rs's blow-up: two stiff undamped disks squeezed between walls, dt far above
    # the critical step (ωΔt ≈ 18).
    "version": 1,
    "name": "blowup",
    "gravity": [0, 0],
    "dt": 1e-3,
    "duration": 10.0,
    "output_every": 1,
    "contact": {"model": "linear", "kn": 1e9, "eta_n": 0, "friction": 0},
    "walls": [{"point": [0, 0], "normal": [1, 0]}, {"point": [3.99, 0], "normal": [-1, 0]}],
    "bodies": [
        {"shape": {"type": "circle", "r": 1}, "position": [1, 0]},
        {"shape": {"type": "circle", "r": 1}, "position": [3, 0]},
    ],
}


def test_a_blow_up_raises_naming_the_step_and_the_body(tmp_path):
    case = dem2d.Case(BLOWUP)
    with pytest.raises(dem2d.BlowupError) as e:
        dem2d.Simulation(case, out=tmp_path / "py").run()
    assert (e.value.step, e.value.time) == (1, 1e-3)
    assert e.value.body in (0, 1)
    assert "energy grew" in e.value.reason
    assert str(e.value).startswith(f"blow-up at step 1 (t = 0.001), body {e.value.body}: ")
    # The command line's message, and the same summary.
    case.save(tmp_path / "blowup.json")
    code, _, err = cli("run", tmp_path / "blowup.json", "--out", tmp_path / "cli", "--quiet", check=False)
    assert code == 1
    assert f"{tmp_path / 'blowup.json'}: {e.value}".replace(
        str(tmp_path / "py"), str(tmp_path / "cli")
    ) in err
    s = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert s["status"] == "blowup" and s["error"] == str(e.value).split("; output so far")[0]
    # Without an output directory too.
    with pytest.raises(dem2d.BlowupError, match=r"^blow-up at step 1 \(t = 0.001\), body"):
        dem2d.Simulation(case).run()
