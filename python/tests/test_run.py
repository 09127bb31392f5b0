"""signorini.run: the same numbers as the CLI, from a path, TOML text or a
dict; typed errors; Ctrl-C keeps the partial result."""

import _thread
import csv
import pathlib
import signal
import subprocess
import threading

import numpy as np
import pytest

import signorini

from conftest import EXE, ROOT

SCENE = ROOT / "data/scenes/bar-dirichlet.toml"


def test_path_text_and_dict_give_the_cli_numbers(tmp_path, exe):
    a = signorini.run(SCENE)
    b = signorini.run(SCENE.read_text())
    c = signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "mass": "mod", "scheme": "newmark-cn", "ratio": 10.0, "t_end": 3.0}})
    for r in (b, c):
        assert np.array_equal(a.t, r.t) and np.array_equal(a.tip, r.tip) and np.array_equal(a.lam, r.lam)
    assert a.t.dtype == np.float64 and a.t.shape == (2401,) and a.status == "ok" and a.steps == 2400
    out = tmp_path / "run"
    subprocess.run([str(exe), "run", str(SCENE), "--out", str(out)], check=True, capture_output=True)
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    # The CSV prints 13 significant digits of the same floats.
    assert np.allclose(a.tip, [float(r["u_contact"]) for r in rows], rtol=1e-12, atol=1e-14)


def test_bad_input_names_the_field():
    with pytest.raises(signorini.SceneError, match="bar.elements"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": [80], "ratio": 10.0}})
    with pytest.raises(ValueError, match="bar.dt"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "dt": float("nan")}})
    with pytest.raises(signorini.SceneError, match="bar.scheme"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "ratio": 10.0, "scheme": "nope"}})
    with pytest.raises(signorini.SceneError, match="object"):
        signorini.run({"bar": object()})


def test_ctrl_c_keeps_the_partial_result():
    # About a second of stepping; interrupted after 0.3 s.
    long = {"bar": {"benchmark": "bar-dirichlet", "elements": 400, "mass": "mod", "scheme": "newmark-cn", "ratio": 1.0, "t_end": 3000.0}}
    # interrupt_main does nothing when SIGINT is ignored (a process started
    # in the background by a shell): Python's own handler, for this test.
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Timer(0.3, _thread.interrupt_main).start()
        with pytest.raises(KeyboardInterrupt) as e:
            signorini.run(long)
    finally:
        signal.signal(signal.SIGINT, old)
    part = e.value.partial
    assert 0 < part.t.size < 1_200_001 and "interrupted" in part.status


def cli(tmp_path, scene_text, name):
    if not EXE.exists():
        pytest.skip(f"the signorini command is not built ({EXE})")
    exe = EXE
    path = tmp_path / f"{name}.toml"
    path.write_text(scene_text)
    out = tmp_path / name
    subprocess.run([str(exe), "run", str(path), "--out", str(out)], check=True, capture_output=True)
    return path, out


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def col(rs, k):
    return np.array([float(r[k]) if r[k] != "" else np.nan for r in rs])


def test_norms_are_the_cli_norms(tmp_path):
    text = SCENE.read_text()
    path, out = cli(tmp_path, text, "dirichlet")
    r = signorini.run(path)
    (want,) = rows(out / "norms.csv")
    assert set(r.norms) >= {"linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy", "lambda_tv_ratio"}
    for k in ("linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy"):
        assert r.norms[k] == pytest.approx(float(want[k]), rel=1e-9), k
    # No exact solution, no norms.
    assert signorini.run(ROOT / "data/scenes/bar-two-walls.toml").norms is None


def test_every_contact_is_recorded_as_the_cli_writes_it(tmp_path):
    path, out = cli(tmp_path, (ROOT / "data/scenes/bar-two-walls.toml").read_text(), "walls")
    r = signorini.run(path)
    rs = rows(out / "series.csv")
    assert r.contact_dofs == [0, 100] and r.contact_u.shape == (r.t.size, 2) and r.forces.shape == (r.t.size, 2)
    assert r.contact_u.dtype == np.float64 and r.active.dtype == np.bool_
    for i in range(2):
        np.testing.assert_allclose(r.contact_u[:, i], col(rs, f"u_c{i}"), rtol=1e-12, atol=1e-14)
        f = col(rs, f"lambda_{i}")
        stepped = ~np.isnan(f)
        np.testing.assert_allclose(r.forces[stepped, i], f[stepped], rtol=1e-12, atol=1e-14)
    # Both walls are hit.
    assert (np.abs(r.forces[:, 0]) > 0).any() and (np.abs(r.forces[:, 1]) > 0).any()


def test_beam_fields_are_the_cli_snapshots(tmp_path):
    text = '[beam]\nscene = "fig2"\nt_end = 0.05\n\n[output]\nevery = 1\nsnapshots_every = 100\n'
    path, out = cli(tmp_path, text, "beam")
    r = signorini.run(path, fields_every=100)
    snaps = rows(out / "snapshots.csv")
    J = 19
    assert r.fields.shape == (r.fields_t.size, 2 * J) and r.fields_t.size == 11
    got = np.asarray(r.fields)[:, 0::2]  # node values 1..J (slopes skipped)
    for k, t in enumerate(r.fields_t):
        at = [s for s in snaps if abs(float(s["t_s"]) - t) < 1e-12]
        want = np.array([float(s["u_m"]) for s in sorted(at, key=lambda s: int(s["n"]))])
        assert want.size == J + 1
        np.testing.assert_allclose(got[k], want[1:], rtol=1e-11, atol=1e-14)
    # The beam computes no energy unless asked (as the CLI).
    assert r.energy.size == 0 and signorini.run(path, energy=True).energy.size >= r.t.size - 1


def test_blow_up_raises_with_step_and_time_and_keeps_the_partial_run():
    # A state that overflows (the CLI's reliability test).
    bad = {"bar": {"elements": 10, "dt": 0.01, "initial_displacement": 0.0, "initial_velocity": 1e300, "body_force": 1e300}}
    with pytest.raises(signorini.BlowUp, match="at step") as e:
        signorini.run(bad)
    part = e.value.partial
    assert 0 < part.t.size < 101 and "blew up" in part.status and part.norms is None


def test_run_bad_arguments():
    with pytest.raises(signorini.SceneError, match="fields_every"):
        signorini.run(SCENE, fields_every=-1)
    with pytest.raises(signorini.SceneError, match="fields_every"):
        signorini.run(SCENE, fields_every="10")
    with pytest.raises(signorini.SceneError, match="energy"):
        signorini.run(SCENE, energy="yes")
    with pytest.raises(signorini.SceneError, match="bar.elements"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": -80, "ratio": 10.0}})
    with pytest.raises(signorini.SceneError, match="bar.mass"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "ratio": 10.0, "mass": 3}})
    with pytest.raises(signorini.SceneError, match="bar.t_end"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "ratio": 10.0, "t_end": float("inf")}})
    with pytest.raises(signorini.SceneError):
        signorini.run({"nothing": {}})
    with pytest.raises(signorini.SceneError):
        signorini.run(42)


def test_a_p2_bar_has_the_cli_norms(tmp_path):
    text = '[bar]\nbenchmark = "bar-dirichlet"\nelements = 20\ndegree = 2\nmass = "mod"\nscheme = "newmark-cn"\nratio = 10.0\nt_end = 3.0\n'
    path, out = cli(tmp_path, text, "p2")
    r = signorini.run(path)
    (want,) = rows(out / "norms.csv")
    assert r.fields.shape == (0, 40) and r.contact_dofs == [0]
    for k in ("linf_l2_u", "l2_l2_u", "l2_lambda"):
        assert r.norms[k] == pytest.approx(float(want[k]), rel=1e-9), k
    # P1 at the same dofs is a different discretisation: not the same numbers.
    p1 = signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 40, "mass": "mod", "scheme": "newmark-cn", "ratio": 20.0, "t_end": 3.0}})
    assert p1.norms["l2_l2_u"] != pytest.approx(r.norms["l2_l2_u"], rel=1e-6)


def test_a_reduced_model_gives_the_cli_numbers(tmp_path):
    """`reduce = { modes = 8 }` acts in Python as in `signorini run` (one
    `Scene::instantiate` for both): a reduced bar's norms and contact series,
    a reduced beam's tip and snapshots (the reconstructed full field)."""
    bar = '[bar]\nbenchmark = "bar-dirichlet"\nelements = 40\nmass = "mod"\nscheme = "newmark-cn"\nratio = 10.0\nt_end = 3.0\nreduce = { modes = 8 }\n'
    path, out = cli(tmp_path, bar, "reduced-bar")
    r = signorini.run(path)
    (want,) = rows(out / "norms.csv")
    for k in ("linf_l2_u", "l2_l2_u", "linf_v_u", "l2_lambda", "linf_energy"):
        assert r.norms[k] == pytest.approx(float(want[k]), rel=1e-9), k
    np.testing.assert_allclose(r.tip, col(rows(out / "series.csv"), "u_contact"), rtol=1e-12, atol=1e-14)
    # The reduction acts: the full model's numbers differ.
    full = signorini.run(bar.replace("reduce = { modes = 8 }\n", ""))
    assert abs(full.norms["linf_l2_u"] - r.norms["linf_l2_u"]) > 1e-6 * r.norms["linf_l2_u"]
    beam = '[beam]\nscene = "fig2"\nt_end = 0.05\nreduce = { modes = 8 }\n\n[output]\nsnapshots_every = 100\n'
    path, out = cli(tmp_path, beam, "reduced-beam")
    r = signorini.run(path, fields_every=100)
    np.testing.assert_allclose(r.tip, col(rows(out / "series.csv"), "tip_m"), rtol=1e-11, atol=1e-14)
    snaps = rows(out / "snapshots.csv")
    last = [s for s in snaps if abs(float(s["t_s"]) - r.fields_t[-1]) < 1e-12]
    want = np.array([float(s["u_m"]) for s in sorted(last, key=lambda s: int(s["n"]))])
    np.testing.assert_allclose(np.asarray(r.fields)[-1, 0::2], want[1:], rtol=1e-10, atol=1e-13)


def test_an_event_driven_run_logs_its_events_at_the_closed_form_times(tmp_path, exe):
    """The undamped impact oscillator x'' + x = cos(2t) from rest, stop at
    0.2: x(t) = (cos 2t − cos t)/(1 − 4) until the first impact, whose time
    is found here by bisection on that closed form; the event log (the same
    rows as the CLI's events.csv) has it, and each impact obeys Newton's law."""
    scene = {"oscillator": {"mass": 1.0, "stiffness": 1.0, "damping_ratio": 0.0, "stop": 0.2, "restitution": 0.8, "scheme": "event-driven",
                            "initial_displacement": 0.0, "initial_velocity": 0.0, "dt": 1e-3, "t_end": 20.0},
             "forcing": {"amplitude": 1.0, "omega": 2.0}}
    r = signorini.run(scene)
    ev = r.events
    assert ev is not None and len(ev["t"]) >= 2
    x = lambda t: (np.cos(2 * t) - np.cos(t)) / -3.0
    dx = lambda t: (-2 * np.sin(2 * t) + np.sin(t)) / -3.0
    # The first crossing of 0.2: bracket it on a fine grid, then bisect.
    grid = np.linspace(0.0, 20.0, 200001)
    i = int(np.argmax(x(grid) >= 0.2))
    a, b = grid[i - 1], grid[i]
    for _ in range(100):
        m = 0.5 * (a + b)
        a, b = (m, b) if x(m) < 0.2 else (a, m)
    assert abs(ev["t"][0] - a) <= 1e-12 * a
    assert abs(ev["velocity_before"][0] - dx(a)) <= 1e-10
    assert all(k == "impact" for k in ev["kind"])
    assert np.allclose(ev["velocity_after"], -0.8 * ev["velocity_before"], rtol=1e-14, atol=0)
    # A time-stepping scheme has no event log.
    assert signorini.run({**scene, "oscillator": {**scene["oscillator"], "scheme": "ps(0.8)"}}).events is None
    # The CLI writes the same rows.
    out = tmp_path / "ed"
    toml = "[oscillator]\n" + "".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in scene["oscillator"].items()) + "[forcing]\namplitude = 1.0\nomega = 2.0\n"
    (tmp_path / "ed.toml").write_text(toml)
    subprocess.run([str(exe), "run", str(tmp_path / "ed.toml"), "--out", str(out)], check=True, capture_output=True)
    with open(out / "events.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["t", "kind", "contact", "velocity_before", "velocity_after", "impulse"]
    assert len(rows) == len(ev["t"])
    assert all(abs(float(row["t"]) - t) <= 1e-15 * t for row, t in zip(rows, ev["t"]))


def test_a_massless_contact_node_lands_and_leaves_without_impacts(tmp_path, exe):
    """bar-dirichlet with mass "mod" (a massless contact node), plain and
    reduced to 8 modes, event-driven: the node lands once and leaves once,
    with no impulse (the massive velocities do not jump), near the
    continuous problem's contact interval [1, 2]; the CLI logs the same
    rows. A restitution above 0 is refused naming it."""
    for reduce in (None, {"modes": 8}):
        bar = {"benchmark": "bar-dirichlet", "elements": 40, "mass": "mod", "scheme": "event-driven", "ratio": 10.0, "t_end": 3.0}
        if reduce:
            bar["reduce"] = reduce
        r = signorini.run({"bar": bar})
        ev = r.events
        assert list(ev["kind"]) == ["impact", "release"]
        assert np.all(np.asarray(ev["impulse"]) == 0.0) and np.all(np.asarray(ev["velocity_after"]) == 0.0)
        assert abs(ev["t"][0] - 1.0) < 0.05 and abs(ev["t"][1] - 2.0) < 0.06
        out = tmp_path / f"m{bool(reduce)}"
        toml = "[bar]\n" + "".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in bar.items() if k != "reduce")
        if reduce:
            toml += "reduce = { modes = 8 }\n"
        (tmp_path / "m.toml").write_text(toml)
        subprocess.run([str(exe), "run", str(tmp_path / "m.toml"), "--out", str(out)], check=True, capture_output=True)
        with open(out / "events.csv") as f:
            rows = list(csv.DictReader(f))
        assert [row["kind"] for row in rows] == list(ev["kind"])
        assert all(abs(float(row["t"]) - t) <= 1e-15 * t for row, t in zip(rows, ev["t"]))
    with pytest.raises(Exception, match="restitution"):
        signorini.run({"bar": {**bar, "scheme": "event-driven(0.5)"}})
