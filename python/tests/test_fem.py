"""signorini.fem against matrices assembled here from the element formulas,
and kappa_h against numpy's dense eigenvalues."""

import numpy as np
import pytest

import signorini
from signorini import fem


def assemble_bar(m, mass, c=1.0, length=1.0):
    """P1 bar on [0, L], node m clamped (not an unknown), contact at node 0."""
    h = length / m
    M = np.zeros((m + 1, m + 1))
    K = np.zeros((m + 1, m + 1))
    for e in range(m):
        idx = np.ix_([e, e + 1], [e, e + 1])
        K[idx] += c * c / h * np.array([[1.0, -1.0], [-1.0, 1.0]])
        if mass == "std":
            M[idx] += h / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
        elif mass == "lumped":
            M[idx] += h / 2 * np.eye(2)
        elif mass == "mod" and e > 0:  # the element [0, h] carries no mass
            M[idx] += h / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    return M[:m, :m], K[:m, :m]


def assemble_beam(J, length=1.0, k2=1.0):
    h = length / J
    Me = h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h], [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    Ke = k2 / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h], [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    n = 2 * (J + 1)
    M, K = np.zeros((n, n)), np.zeros((n, n))
    for e in range(J):
        idx = np.ix_(range(2 * e, 2 * e + 4), range(2 * e, 2 * e + 4))
        M[idx] += Me
        K[idx] += Ke
    return M[2:, 2:], K[2:, 2:]  # node 0 clamped


@pytest.mark.parametrize("mass", ["std", "lumped", "mod"])
def test_bar_matrices_are_the_assembled_ones(mass):
    a = fem.bar(7, mass, length=2.0, wave_speed=1.5)
    M, K = assemble_bar(7, mass, c=1.5, length=2.0)
    assert a.M.dtype == np.float64 and a.M.shape == (7, 7) and a.mass_band.shape == (2, 7)
    np.testing.assert_allclose(a.M, M, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(a.K, K, rtol=1e-14, atol=1e-15)
    # Upper band storage: ab[p + i - j, j] = A[i, j].
    assert a.stiffness_band[1, 3] == K[3, 3] and a.stiffness_band[0, 3] == K[2, 3]
    assert a.massless == ([0] if mass == "mod" else [])
    np.testing.assert_allclose(a.x, np.arange(7) * 2.0 / 7)


def test_beam_matrices_are_the_assembled_ones():
    b = fem.beam(5, length=1.5, k2=2.0)
    M, K = assemble_beam(5, length=1.5, k2=2.0)
    assert b.half_bandwidth == 3 and b.mass_band.shape == (4, 10)
    np.testing.assert_allclose(b.M, M, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(b.K, K, rtol=1e-13, atol=1e-12)


def kappa_dense(M, K, massless=()):
    keep = [i for i in range(M.shape[0]) if i not in massless]
    M, K = M[np.ix_(keep, keep)], K[np.ix_(keep, keep)]
    return max(np.linalg.eigvals(np.linalg.solve(M, K)).real)


@pytest.mark.parametrize("mass", ["std", "lumped", "mod", "mod2", "transfer"])
def test_kappa_h_is_the_largest_generalized_eigenvalue(mass):
    a = fem.bar(12, mass)
    assert a.kappa_h() == pytest.approx(kappa_dense(a.M, a.K, a.massless), rel=1e-11)
    b = fem.beam(6, k2=3.0)
    assert b.kappa_h() == pytest.approx(kappa_dense(b.M, b.K), rel=1e-11)
    # Lumped P1, clamped-free pair of ends: 4c²/h² sin²((2m-1)π/(4m)) in closed form.
    m = 12
    assert fem.bar(m, "lumped").kappa_h() == pytest.approx(4 * m * m * np.sin((2 * m - 1) * np.pi / (4 * m)) ** 2, rel=1e-12)


def test_bad_input_names_the_argument():
    for call, field in [
        (lambda: fem.bar("10"), "elements"),
        (lambda: fem.bar(1), "elements"),
        (lambda: fem.bar(-3), "elements"),
        (lambda: fem.bar(10.5), "elements"),  # 10.0 is 10 (issue 22 item 7)
        (lambda: fem.bar(2**40), "elements"),
        (lambda: fem.bar(10, mass="nope"), "mass"),
        (lambda: fem.bar(10, mass=3), "mass"),
        (lambda: fem.bar(10, length=float("nan")), "length"),
        (lambda: fem.bar(10, wave_speed=-1.0), "wave_speed"),
        (lambda: fem.bar(10, right_end="hinged"), "right_end"),
        (lambda: fem.bar(10, contacts=[99]), "contacts"),
        (lambda: fem.bar(10, contacts=["a"]), "contacts"),
        (lambda: fem.beam(0), "elements"),
        (lambda: fem.beam(5, k2=float("inf")), "k2"),
        (lambda: fem.beam([5]), "elements"),
    ]:
        with pytest.raises(signorini.SceneError, match="^" + field):
            call()


def test_p2_bar_is_the_assembled_quadratic_element():
    m, h = 4, 0.25
    Me = h / 30 * np.array([[4.0, 2.0, -1.0], [2.0, 16.0, 2.0], [-1.0, 2.0, 4.0]])
    Ke = 1 / (3 * h) * np.array([[7.0, -8.0, 1.0], [-8.0, 16.0, -8.0], [1.0, -8.0, 7.0]])
    n = 2 * m + 1
    M, K = np.zeros((n, n)), np.zeros((n, n))
    for e in range(m):
        idx = np.ix_(range(2 * e, 2 * e + 3), range(2 * e, 2 * e + 3))
        M[idx] += Me
        K[idx] += Ke
    a = fem.bar(m, "std", degree=2)
    assert a.half_bandwidth == 2 and a.n == 2 * m
    np.testing.assert_allclose(a.M, M[:-1, :-1], rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(a.K, K[:-1, :-1], rtol=1e-14, atol=1e-13)
    np.testing.assert_allclose(a.x, np.arange(2 * m) * h / 2)
    assert a.kappa_h() == pytest.approx(kappa_dense(a.M, a.K), rel=1e-11)
    for bad, field in [(0, "degree"), (4, "degree"), (2.5, "degree"), (True, "degree")]:
        with pytest.raises(signorini.SceneError, match="^" + field):
            fem.bar(m, degree=bad)
    with pytest.raises(signorini.SceneError, match="^mass"):
        fem.bar(m, "mod3", degree=2)
