"""signorini.sweep: the files of `signorini sweep` (same engine, another
front end), from a path or a dict; Ctrl-C keeps whole runs; typed bad input."""

import _thread
import csv
import signal
import subprocess
import threading

import numpy as np
import pytest

import signorini
from conftest import ROOT

SCENE = ROOT / "data/scenes/oscillator.toml"


def columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def test_the_files_of_signorini_sweep(tmp_path, exe):
    out = tmp_path / "cli"
    subprocess.run([str(exe), "sweep", str(SCENE), "--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "7", "--transient", "200", "--record", "10", "--out", str(out)], check=True, capture_output=True)
    r = signorini.sweep(SCENE, "forcing.omega", 1.6, 2.2, 7, transient=200, record=10, out=tmp_path / "py")
    for name, table in (("sweep.csv", r.sweep), ("summary.csv", r.summary), ("impacts.csv", r.impacts)):
        rows = columns(out / name)
        assert list(table) == list(rows[0])
        assert (tmp_path / "py" / name).read_bytes() == (out / name).read_bytes(), name
        for k, v in table.items():
            if isinstance(v, np.ndarray):
                # The counts are int64 (issue 22 item 10), the rest float64.
                counts = k in ("run", "stop", "impacts", "period", "poincare_points", "steps")
                assert v.dtype == (np.int64 if counts else np.float64) and np.array_equal(v, [float(x[k]) if x[k] else np.nan for x in rows], equal_nan=True), (name, k)
            else:
                assert v == [x[k] for x in rows], (name, k)
    assert f'id = "{r.id}"' in (out / "sweep.toml").read_text()
    # The oscillator hits its stop about once per forcing period at these Ω.
    assert np.all(np.abs(r.summary["impacts_per_period"] - 1) < 1e-3) and len(r.summary["run"]) == 7


def test_a_dict_scene_and_a_map():
    doc = {
        "oscillator": {"mass": 1.0, "stiffness": 1.0, "damping_ratio": 0.05, "stop": 0.2, "restitution": 0.8, "dt": 1e-3, "t_end": 100.0},
        "forcing": {"amplitude": 1.0, "omega": 2.0},
    }
    a = signorini.sweep(doc, "forcing.omega", 1.6, 2.2, 4, transient=50, record=5)
    b = signorini.sweep(SCENE, "forcing.omega", 1.6, 2.2, 4, transient=50, record=5)
    assert np.array_equal(a.sweep["displacement"], b.sweep["displacement"]) and a.id != b.id
    m = signorini.sweep(doc, "forcing.omega", 1.6, 2.2, 3, param2="forcing.amplitude", start2=0.5, stop2=1.0, count2=2, transient=50, record=5, impacts=False)
    assert list(m.summary)[-1] == "param2" and len(m.summary["run"]) == 6 and m.impacts is None
    np.testing.assert_array_equal(m.summary["param2"], [0.5, 0.5, 0.5, 1.0, 1.0, 1.0])


def test_ctrl_c_keeps_whole_runs(tmp_path):
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Timer(0.5, _thread.interrupt_main).start()
        with pytest.raises(KeyboardInterrupt) as e:
            signorini.sweep(SCENE, "forcing.omega", 1.6, 2.2, 60, transient=100, record=10, threads=1, out=tmp_path / "s")
    finally:
        signal.signal(signal.SIGINT, old)
    part = e.value.partial
    runs = part.summary["run"] if part.summary is not None else np.zeros(0)
    assert 0 < len(runs) < 60
    np.testing.assert_array_equal(runs, np.arange(len(runs)))
    assert set(np.unique(part.sweep["run"])) <= set(runs)
    # And the folder resumes to the whole sweep.
    whole = signorini.sweep(SCENE, "forcing.omega", 1.6, 2.2, 60, transient=100, record=10, resume=True, out=tmp_path / "s")
    assert len(whole.summary["run"]) == 60


def test_resuming_a_missing_folder_is_an_os_error_with_an_empty_partial(tmp_path):
    with pytest.raises(OSError, match="sweep.toml") as e:
        signorini.sweep(SCENE, "forcing.omega", 1.6, 2.2, 4, resume=True, out=tmp_path / "missing")
    assert e.value.partial.summary is None and e.value.partial.lines == []


def test_bad_input_names_the_argument():
    for kw, field in [
        (dict(param="forcing.nothing"), "param forcing.nothing"),
        (dict(count=0), "count"),
        (dict(count=2.5), "count"),
        (dict(start="a"), "start"),
        (dict(stop=float("nan")), "stop"),
        (dict(shard=(3, 2)), "shard"),
        (dict(transient=-1.0), "transient"),
        (dict(threads=0), "threads"),
        (dict(log="yes"), "log"),
        (dict(resume=True), "resume"),
        (dict(log=True, start=-1.0), "start"),
        (dict(period_tol=2.0), "period_tol"),
    ]:
        args = dict(param="forcing.omega", start=1.6, stop=2.2, count=3)
        args.update(kw)
        with pytest.raises(signorini.SceneError, match="^" + field):
            signorini.sweep(SCENE, args.pop("param"), args.pop("start"), args.pop("stop"), args.pop("count"), **args)
    with pytest.raises(signorini.SceneError, match="scene"):
        signorini.sweep(3, "forcing.omega", 1.6, 2.2, 3)
