"""signorini.basins: the oscillator's two coexisting period-1 attractors at
Omega = 1.85 against an exact flow written here (the free response in closed
form, the impacting orbit a fixed point of the stroboscopic map with one
impact), the files byte for byte those of `signorini basins` (with known
orbits, and sharded then `signorini merge`), Ctrl-C keeping whole rows, and
bad input named."""

import _thread
import math
import signal
import subprocess
import threading

import numpy as np
import pytest

import signorini

OMEGA, ZETA, GAP, R = 1.85, 0.05, 0.5, 0.8
SCENE = f"""
[oscillator]
mass = 1.0
stiffness = 1.0
damping_ratio = {ZETA}
stop = {GAP}
restitution = {R}
initial_displacement = 0.0
initial_velocity = 0.0
dt = 1e-2
t_end = 10.0
scheme = "event-driven({R})"
[forcing]
amplitude = 1.0
omega = {OMEGA}
"""
KEYS = ("oscillator.initial_displacement", "oscillator.initial_velocity")
GRID, XR, VR = (9, 7), (-2.0, 0.4), (-1.5, 1.5)


def free_response():
    """x'' + 2 zeta x' + x = cos(Omega t): X cos(Omega t - phi) at t = 0."""
    c, k = 2 * ZETA, 1 - OMEGA**2
    amp, phi = 1 / math.hypot(k, c * OMEGA), math.atan2(c * OMEGA, k)
    return np.array([amp * math.cos(phi), amp * OMEGA * math.sin(phi)])


def flow(x, v, t0, t1):
    """The exact flow of x'' + 2 zeta x' + x = cos(Omega t) from (x, v) at t0
    to t1 with impacts at x = GAP (v -> -R v); returns (x, v, impacts)."""
    c, k = 2 * ZETA, 1 - OMEGA**2
    den = k * k + (c * OMEGA) ** 2
    a, b = k / den, c * OMEGA / den  # particular: a cos(Omega t) + b sin(Omega t)
    wd = math.sqrt(1 - ZETA**2)
    impacts = 0
    while True:
        px = lambda t: a * math.cos(OMEGA * t) + b * math.sin(OMEGA * t)  # noqa: E731
        pv = lambda t: OMEGA * (-a * math.sin(OMEGA * t) + b * math.cos(OMEGA * t))  # noqa: E731
        A = x - px(t0)
        B = (v - pv(t0) + ZETA * A) / wd

        def at(t):
            s = t - t0
            e = math.exp(-ZETA * s)
            h = e * (A * math.cos(wd * s) + B * math.sin(wd * s))
            hv = e * ((-ZETA * A + wd * B) * math.cos(wd * s) + (-ZETA * B - wd * A) * math.sin(wd * s))
            return h + px(t), hv + pv(t)

        # The first crossing of the stop after t0, on a fine scan then bisection.
        n = max(1, int((t1 - t0) / 1e-3))
        hit, lo = None, t0
        for m in range(1, n + 1):
            hi = t0 + (t1 - t0) * m / n
            if at(hi)[0] > GAP:
                hit = (lo, hi)
                break
            lo = hi
        if hit is None:
            x, v = at(t1)
            return x, v, impacts
        lo, hi = hit
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if at(mid)[0] > GAP:
                hi = mid
            else:
                lo = mid
        x, v = GAP, -R * at(hi)[1]
        t0 = hi
        impacts += 1


def test_two_attractors_at_the_exact_flow_and_the_map(tmp_path):
    r = signorini.basins(SCENE, *KEYS, grid=GRID, x_range=XR, v_range=VR, out=tmp_path)
    n = GRID[0] * GRID[1]
    assert r.complete and r.map.shape == (GRID[1], GRID[0]) and len(r.attractor) == n
    np.testing.assert_array_equal(r.i, np.arange(n) % GRID[0])
    np.testing.assert_allclose(r.x, XR[0] + (XR[1] - XR[0]) * (np.arange(n) % GRID[0]) / (GRID[0] - 1), rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.v, VR[0] + (VR[1] - VR[0]) * (np.arange(n) // GRID[0]) / (GRID[1] - 1), rtol=0, atol=1e-12)
    assert set(r.label) == {"p1-i0", "p1-i1"} and np.all(r.period == 1) and not r.sticking.any()
    free = free_response()
    T = 2 * math.pi / OMEGA
    for k, c in enumerate(r.attractors["first_cell"]):
        s = r.attractors["state"][k]
        x, v, hits = flow(s[0], s[1], 0.0, T)
        assert hits == r.impacts_per_period[c]
        # A fixed point of the exact map, to the classification's tolerance.
        assert abs(x - s[0]) < 1e-6 and abs(v - s[1]) < 1e-6, (k, s, x, v)
        if hits == 0:
            np.testing.assert_allclose(s, free, rtol=0, atol=1e-7)
    # Ids in the order the cells first reach them; every cell on its own.
    first = {}
    for c in range(n):
        want = first.setdefault(r.impacts_per_period[c], len(first))
        assert r.attractor[c] == want
        np.testing.assert_allclose(r.state[c], r.attractors["state"][want], rtol=0, atol=1e-3)
    np.testing.assert_array_equal(r.attractors["cells"], [np.sum(r.attractor == k) for k in range(2)])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["basins.csv", "basins.svg", "basins.toml"]
    assert (tmp_path / "basins.csv").read_text().count("\n") == n + 1


def command(exe, out, *extra):
    scene = out.parent / "osc.toml"
    scene.write_text(SCENE)
    args = [str(exe), "basins", str(scene), "--x", KEYS[0], "--v", KEYS[1], "--grid", *map(str, GRID)]
    args += ["--x-range", *map(str, XR), "--v-range", *map(str, VR), "--out", str(out), *extra]
    p = subprocess.run(args, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_the_files_are_the_commands_byte_for_byte(tmp_path, exe):
    branch = signorini.continuation(SCENE, "forcing.omega", 1.85, 1.6, out=tmp_path / "cont")
    command(exe, tmp_path / "cli", "--orbits", str(tmp_path / "cont" / "branch.csv"))
    r = signorini.basins(SCENE, *KEYS, grid=GRID, x_range=XR, v_range=VR, orbits=branch)
    assert any(lab.startswith("branch0:") for lab in r.label)
    r.write(tmp_path / "py")
    for f in ["basins.csv", "basins.svg", "basins.toml"]:
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    # Shards written from Python, merged by the command: the whole grid's files.
    for i in (1, 0, 2):
        s = signorini.basins(SCENE, *KEYS, grid=GRID, x_range=XR, v_range=VR, orbits=tmp_path / "cont", shard=(i, 3), out=tmp_path / f"s{i}")
        assert s.map is None and s.svg is None and s.cells == (i * 63 // 3, (i + 1) * 63 // 3)
    p = subprocess.run([str(exe), "merge", *(str(tmp_path / f"s{i}") for i in range(3)), "--out", str(tmp_path / "merged")], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    for f in ["basins.csv", "basins.svg", "basins.toml"]:
        assert (tmp_path / "merged" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f


def test_ctrl_c_keeps_whole_rows(tmp_path):
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Timer(0.5, _thread.interrupt_main).start()
        with pytest.raises(KeyboardInterrupt) as e:
            signorini.basins(SCENE, *KEYS, grid=(100, 100), x_range=XR, v_range=VR, threads=1, out=tmp_path)
    finally:
        signal.signal(signal.SIGINT, old)
    part = e.value.partial
    n = len(part.attractor)
    assert 0 < n < 10_000 and not part.complete and part.map is None
    np.testing.assert_array_equal(part.i, np.arange(n) % 100)
    assert np.all(part.period == 1)
    rows = (tmp_path / "basins.csv").read_text().splitlines()
    assert len(rows) == n + 1 and rows[-1].startswith(f"{(n - 1) % 100},{(n - 1) // 100},")


@pytest.mark.parametrize(
    "field, kwargs",
    [
        ("x", dict(x="oscillator.nope")),
        ("v", dict(v=KEYS[0])),
        ("grid", dict(grid=(0, 5))),
        ("grid", dict(grid=(3,))),
        ("grid[1]", dict(grid=(3, 2.5))),
        ("x_range", dict(x_range=(-1.0, math.inf))),
        ("v_range", dict(v_range=("a", 1.0))),
        ("max_period", dict(max_period=0)),
        ("tol", dict(tol=2.0)),
        ("match_tol", dict(match_tol=0.0)),
        ("transient", dict(transient=-1)),
        ("shard", dict(shard=(3, 3))),
        ("threads", dict(threads=0)),
        ("orbits", dict(orbits="/nonexistent/branch.csv")),
        ("orbits", dict(orbits=3)),
    ],
)
def test_bad_input_is_named(field, kwargs):
    a = dict(x=KEYS[0], v=KEYS[1], grid=(3, 2), x_range=XR, v_range=VR, transient=1)
    a.update(kwargs)
    with pytest.raises(signorini.SceneError, match="^" + field.replace("[", r"\[").replace("]", r"\]")):
        signorini.basins(SCENE, **a)


def test_a_scheme_other_than_the_exact_one_is_refused():
    with pytest.raises(signorini.SceneError, match="scheme"):
        signorini.basins(SCENE.replace(f'scheme = "event-driven({R})"', 'scheme = "paoli-schatzman"'), *KEYS, grid=(2, 2), x_range=XR, v_range=VR)
