"""signorini.exact.backbone and the 'nonsmooth-mode' solution (docs/theory.md
§11) against numbers found without them: hand values of the closed form,
the linear periods, bar-dirichlet, and a Courant-one run of the bar written
here (nodally exact when impacts and releases fall on time levels)."""

import numpy as np
import pytest

import signorini
from signorini import exact


def courant_one(gap, u0, u1, levels):
    """The lumped central difference at dx/dt = c (docs/theory.md §4.10):
    d'Alembert's recurrence inside, the clamped node at 0, the contact node
    by the characteristic rule max(gap, 2 u_1 - u_0^{n-1} - s)."""
    run = [np.asarray(u0, float), np.asarray(u1, float)]
    s = 0.0
    for _ in range(levels - 1):
        prev, cur = run[-2], run[-1]
        nxt = np.zeros_like(cur)
        nxt[1:-1] = cur[2:] + cur[:-2] - prev[1:-1]
        free = 2.0 * cur[1] - prev[0] - s
        nxt[0] = max(gap, free)
        s = free - nxt[0]
        run.append(nxt)
    return np.array(run)


def test_hand_values_and_limits():
    # L = c = 1, gap -1/4: threshold c² g²/(2L) = 1/32; at E = 1/2 (Q = 1)
    # T = 3 + 1/4, contact 1 - 1/4, force -cQ = -1.
    b = exact.backbone(gap=-0.25)
    assert (b.family, b.threshold, b.linear_period, b.limit_period) == (1, 1 / 32, 4.0, 3.0)
    p = b(0.5)
    assert p == {"period": 3.25, "contact_time": 0.75, "flight_time": 2.5, "impacts_per_period": 1, "impact_velocity": 1.0, "contact_force": -1.0}
    assert type(p["impacts_per_period"]) is int and type(p["period"]) is float
    # Below the threshold: the linear period 4L/c, no contact.
    low = b(np.array([0.0, 0.01, 1 / 32]))
    assert low["period"].tolist() == [4.0] * 3 and low["impacts_per_period"].tolist() == [0] * 3
    # g = 0: 3L/c at every energy; other L and c scale it.
    flat = exact.backbone(length=2.0, wave_speed=0.5)(np.logspace(-6, 6, 7))
    assert np.all(flat["period"] == 12.0) and np.all(flat["contact_time"] == 4.0)
    # The second family through 4L/(3c): T = 21/16 at E = 1/2, gap -1/4.
    assert exact.backbone(gap=-0.25, family=2)(0.5)["period"] == 21 / 16


def test_the_mode_is_bar_dirichlet_at_energy_one_eighth():
    mode, bench = exact.solution("nonsmooth-mode", energy=0.125), exact.solution("bar-dirichlet")
    x = (np.arange(21) + 0.37) / 21
    t = 0.013 + 0.0151 * np.sqrt(2) * np.arange(300)
    for f in ("u", "u_x", "u_t"):
        a, b = getattr(mode, f)(x[:, None], t[None, :]), getattr(bench, f)(x[:, None], t[None, :])
        assert np.abs(a - b).max() < 1e-14, f
    assert np.array_equal(mode.lam(t), bench.lam(t)) and mode.energy(1.0) == 0.125


def test_against_a_courant_one_bar():
    # gap -1/4, E = 1/2: impact 1.25 after the top, release at 2, period 3.25;
    # with m = 40 every event is on a level (dt = 1/40).
    m, gap, energy = 40, -0.25, 0.5
    mode = exact.solution("nonsmooth-mode", energy=energy, gap=gap)
    x, dt = np.linspace(0.0, 1.0, m + 1), 1.0 / m
    # The stretched bar at rest (docs/theory.md §11.3), u = (Q/c)(L - x), Q = 1.
    u0 = 1.0 - x
    u1 = u0.copy()
    u1[1:-1] = 0.5 * (u0[:-2] + u0[2:])
    u1[0] = u0[1]
    run = courant_one(gap, u0, u1, 300)
    levels = np.arange(run.shape[0]) * dt
    assert np.abs(run - mode.u(x[None, :], levels[:, None])).max() < 1e-12
    back = next(n for n in range(1, 299) if np.abs(run[n] - run[0]).max() + np.abs(run[n + 1] - run[1]).max() < 1e-12)
    held = np.flatnonzero(np.abs(run[: back + 1, 0] - gap) < 1e-12)
    p = exact.backbone(gap=gap)(energy)
    assert back * dt == pytest.approx(p["period"], abs=1e-12)
    assert (held[-1] - held[0]) * dt == pytest.approx(p["contact_time"], abs=1e-12)
    assert np.all(np.diff(held) == 1)  # one contact phase


def test_bad_input_names_the_field():
    for call, field in [
        (lambda: exact.backbone()(-1.0), "energy"),
        (lambda: exact.backbone()(np.nan), "energy"),
        (lambda: exact.backbone(gap=0.5)(0.1), "energy"),
        (lambda: exact.backbone(far_end="free"), "far_end"),
        (lambda: exact.backbone(far_end="pinned"), "far_end"),
        (lambda: exact.backbone(family=0), "family"),
        (lambda: exact.backbone(length=0.0), "length"),
        (lambda: exact.backbone(wave_speed="a"), "wave_speed"),
        (lambda: exact.solution("nonsmooth-mode"), "energy"),
        (lambda: exact.solution("nonsmooth-mode", energy=1.0, u0=0.5), "u0"),
        (lambda: exact.solution("nonsmooth-mode", energy=1.0, family=1.5), "family"),
        (lambda: exact.solution("bar-dirichlet", energy=1.0), "energy"),
    ]:
        with pytest.raises(signorini.SceneError, match=f"^{field}"):
            call()
    with pytest.raises(signorini.SceneError, match=r"^length: 0(\.0)? is not allowed: finite and > 0$"):
        exact.backbone(length=0.0)
