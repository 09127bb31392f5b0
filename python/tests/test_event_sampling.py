"""signorini.run of the event-driven reference is `signorini run`'s run, bit
for bit, however it is sampled (docs/theory.md §9.4): a sample at an
impact's time, dt = 1e-12 and dt beyond the events' spacing, a horizon that
is not N dt in floating point, t_end = 0, Ctrl-C. The CLI's series.csv and
events.csv are rebuilt here from the arrays Python returns, in the CLI's
number format, and compared as text."""

import _thread
import math
import signal
import subprocess
import threading

import numpy as np
import pytest

import signorini


def rust_e(x, digits):
    """`x` as Rust's `{:.<digits>e}` prints it (`1.5e-7`, `0.0e0`)."""
    m, e = f"{x:.{digits}e}".split("e")
    return f"{m}e{int(e)}"


def series_text(r, every=1):
    """The oscillator's series.csv from a run's arrays: `n,t,x,v,lambda_t,
    lambda,energy_t,energy`, `v` the backward difference over the last
    level, 13 significant digits."""
    f = lambda x: rust_e(x, 12)
    lines = ["n,t,x,v,lambda_t,lambda,energy_t,energy"]
    for n in range(0, r.t.size, every):
        if n == 0:
            mid = ",,"
        else:
            v = (r.tip[n] - r.tip[n - 1]) / (r.t[n] - r.t[n - 1])
            mid = f"{f(v)},{f(r.lam_t[n - 1])},{f(r.lam[n - 1])}"
        lines.append(f"{n},{f(r.t[n])},{f(r.tip[n])},{mid},{f(r.energy_t[n])},{f(r.energy[n])}")
    return "\n".join(lines) + "\n"


def events_text(ev):
    """events.csv from a run's event log: 17 significant digits."""
    f = lambda x: rust_e(x, 16)
    lines = ["t,kind,contact,velocity_before,velocity_after,impulse"]
    for i in range(len(ev["t"])):
        lines.append(f"{f(ev['t'][i])},{ev['kind'][i]},{ev['contact'][i]},{f(ev['velocity_before'][i])},{f(ev['velocity_after'][i])},{f(ev['impulse'][i])}")
    return "\n".join(lines) + "\n"


def oscillator(dt, t_end, stop=0.5, x0=0.0, v0=1.0, e=0.8, forcing="", every=1):
    # repr of a float: its shortest round-trip digits (numpy's adds its type).
    dt, t_end = float(dt), float(t_end)
    return (
        f"[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.0\nstop = {stop!r}\nrestitution = {e!r}\n"
        f"initial_displacement = {x0!r}\ninitial_velocity = {v0!r}\ndt = {dt!r}\nt_end = {t_end!r}\nscheme = \"event-driven\"\n"
        f"{forcing}[output]\nevery = {every}\nplots = false\n"
    )


def chatter(dt, every=1):
    """Pushed onto its stop by 1e5 cos t from 1e-9 below it (restitution
    0.5): impacts every 1.4e-7 s halving to 4.4e-9 s, an accumulation at
    4.24e-7 s, all within t_end = 5e-7."""
    return oscillator(dt, 5e-7, stop=0.2, x0=0.199999999, v0=0.0, e=0.5, forcing="[forcing]\namplitude = 1e5\nomega = 1.0\n", every=every)


def same_as_cli(tmp_path, exe, name, text, every=1):
    """signorini.run(text) and the CLI's files of the same scene: the same text."""
    r = signorini.run(text)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    out = tmp_path / name
    subprocess.run([str(exe), "run", str(path), "--out", str(out)], check=True, capture_output=True)
    assert (out / "series.csv").read_text() == series_text(r, every), name
    assert (out / "events.csv").read_text() == events_text(r.events), name
    return r


def final(r):
    """The final level in bits: t, x, the energy (x')."""
    return (r.t[-1].tobytes(), r.tip[-1].tobytes(), r.energy[-1].tobytes())


def test_a_sample_at_an_impact_shows_the_state_after_it(tmp_path, exe):
    """x'' + x = 0 from x = 0, x' = 1, stop 0.5: x = sin t, the first impact
    at pi/6. Sampled at dt = t1/1024 (1024 dt is the located t1 exactly),
    the level at t1 holds the impact: its mean force (1 + e) cos t1 / dt and
    the energy after it, e^2 cos^2 t1 / 2 + sin^2 t1 / 2 (closed forms)."""
    t1 = signorini.run(oscillator(1e-3, 1.0)).events["t"][0]
    assert abs(t1 - math.pi / 6) <= 1e-15 * math.pi / 6
    dt = t1 / 1024
    r = same_as_cli(tmp_path, exe, "aligned", oscillator(dt, 2048 * dt))
    assert r.t[1024] == t1
    c = math.cos(t1)
    assert r.lam[1023] == pytest.approx(1.8 * c / dt, rel=1e-9)
    assert r.energy[1024] == pytest.approx(0.5 * 0.64 * c * c + 0.5 * math.sin(t1) ** 2, abs=1e-14)
    assert r.energy[1023] == pytest.approx(0.5, abs=1e-14)
    # Ending at t1: the velocity after the impact, the same bits with one step.
    a, b = signorini.run(oscillator(dt, t1)), signorini.run(oscillator(t1, t1))
    assert final(a) == final(b) and a.events["t"][-1] == t1
    assert a.energy[-1] == pytest.approx(r.energy[1024], abs=1e-15)


def test_a_tiny_dt_and_a_dt_beyond_the_events_spacing_give_the_same_run(tmp_path, exe):
    runs = [same_as_cli(tmp_path, exe, f"c{i}", chatter(dt, every), every) for i, (dt, every) in enumerate([(1e-12, 5), (1e-8, 1), (5e-7, 1)])]
    assert runs[0].t.size == 500_001 and runs[2].t.size == 2
    ev = runs[1].events
    assert "accumulation" in ev["kind"] and np.diff(ev["t"]).min() < 5e-7 / 100
    for r in runs:
        assert events_text(r.events) == events_text(ev)
        assert final(r) == final(runs[0]) and r.t[-1] == 5e-7


def test_the_last_level_is_at_t_end_once_whatever_dt(tmp_path, exe):
    """t_end = 0.7: 7 x 0.1 is 0.7000000000000001, yet every dt ends at 0.7."""
    ends = []
    for i, (dt, n) in enumerate([(0.1, 7), (0.07, 10), (1e-3, 700), (0.7, 1)]):
        r = same_as_cli(tmp_path, exe, f"h{i}", oscillator(dt, 0.7))
        assert r.t.size == n + 1 and r.t[-1] == 0.7 and r.steps == n and len(r.events["t"]) == 1
        ends.append((final(r), events_text(r.events)))
    assert all(e == ends[0] for e in ends)
    assert 7 * 0.1 != 0.7
    with pytest.raises(signorini.SceneError, match=r"oscillator\.t_end.*not a whole number of steps"):
        signorini.run(oscillator(0.1, 0.75))


def test_t_end_zero_is_refused_naming_the_field():
    for kind, scene in [
        ("oscillator", oscillator(1e-3, 0.0)),
        ("bar", '[bar]\nbenchmark = "bar-dirichlet"\nelements = 10\nscheme = "event-driven"\nratio = 10.0\nt_end = 0.0\n'),
        ("beam", '[beam]\nscene = "fig2"\nscheme = "event-driven"\nt_end = 0.0\n'),
    ]:
        with pytest.raises(signorini.SceneError, match=rf"{kind}\.t_end.*finite and > 0"):
            signorini.run(scene)


def test_ctrl_c_keeps_the_uninterrupted_runs_levels():
    """The partial result of an interrupted run is the run to its last level."""
    forced = "[forcing]\namplitude = 1.0\nomega = 2.0\n"
    scene = lambda t_end: oscillator(1e-4, t_end, stop=0.2, v0=0.0, forcing=forced)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Timer(0.3, _thread.interrupt_main).start()
        with pytest.raises(KeyboardInterrupt) as e:
            signorini.run(scene(200.0))
    finally:
        signal.signal(signal.SIGINT, old)
    part = e.value.partial
    k = part.t.size - 1
    assert 1000 < k < 2_000_000 and "interrupted" in part.status
    full = signorini.run(scene(k * 1e-4))
    for name in ("t", "tip", "lam_t", "lam", "energy_t", "energy"):
        assert getattr(part, name).tobytes() == getattr(full, name).tobytes(), name
    nxt = signorini.run(scene((k + 1) * 1e-4))
    kept = events_text(part.events)
    assert kept.startswith(events_text(full.events)) and events_text(nxt.events).startswith(kept)
