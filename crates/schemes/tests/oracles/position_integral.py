#!/usr/bin/env python3
"""Independent high-precision oracle: the integral of the position over a
flight, int_{t0}^{t0+tau} q(t) dt, of a structure whose flow has a damped
free mode (k = 0 < c), for `ModalFlow::position_integral` (events_flow.rs,
`a_damped_free_modes_integral_keeps_its_digits`).

Cases
-----
one:   1 dof, m = 1.3, no spring, a damper c; load 0.7 + 0.4 sin(1.7 t);
       q0 = 0.3, v0 = -0.2 (classical: the mode k = 0, c/m).
chain: the free 3-dof chain of events_common::chain_matrices(3, true)
       (consistent mass 1/3, 2/3, 1/3 on the diagonal, 1/6 off it; unit
       springs), a dashpot c at dof 0 (the first-order form: the rigid pair
       lambda = 0, -c_eff); load (0.2, 0, 0.1) + (1, 0.5, 0) 0.4 sin(1.7 t);
       q0 = (0.3, -0.1, 0.25), v0 = (-0.2, 0.15, 0.05).
Both from t0 = 1.3, for c in 1e-13 .. 1 and tau in 0.01, 1, 10 (c tau from
1e-15 to 10).

Method
------
The state augmented with the integral w (w' = q), a constant 1 and the
harmonic's sin and cos: z' = B z, z(t0 + tau) = expm(B tau) z(t0), by
mpmath's expm at 50 digits, from the f64 values of every input (mpf of a
Python float is exact). Nothing in common with the modal formulas.

Output
------
position_integral.csv (next to this script): case,c,tau,w_0,...,w_{n-1},
25 significant digits (the chain's row has three w's, the one's one).

Run
---
    python3 position_integral.py     # writes the CSV (a few seconds)
Needs mpmath (1.3).
"""

import os
from mpmath import mp, mpf, matrix, expm, sin, cos

mp.dps = 50

T0 = 1.3
OMEGA = 1.7
AMP = 0.4
CS = [1e-13, 1e-11, 1e-9, 1e-7, 1e-5, 1e-3, 0.1, 1.0]
TAUS = [0.01, 1.0, 10.0]


def case(name, c):
    if name == "one":
        m = matrix([[1.3]])
        k = matrix([[0.0]])
        d = matrix([[c]])
        f = [0.7]
        g = [1.0]
        q0, v0 = [0.3], [-0.2]
    else:
        third, sixth = mpf(1.0 / 3.0), mpf(1.0 / 6.0)
        m = matrix([[third, sixth, 0], [sixth, mpf(2.0 / 3.0), sixth], [0, sixth, third]])
        k = matrix([[1, -1, 0], [-1, 2, -1], [0, -1, 1]])
        d = matrix(3, 3)
        d[0, 0] = c
        f = [0.2, 0.0, 0.1]
        g = [1.0, 0.5, 0.0]
        q0, v0 = [0.3, -0.1, 0.25], [-0.2, 0.15, 0.05]
    return m, k, d, f, g, q0, v0


def integral(name, c, tau):
    m, k, d, f, g, q0, v0 = case(name, mpf(c))
    n = m.rows
    minv = m ** -1
    dim = 3 * n + 3
    b = matrix(dim, dim)
    mk, md = minv * k, minv * d
    for i in range(n):
        b[i, n + i] = 1
        b[2 * n + i, i] = 1
        for j in range(n):
            b[n + i, j] = -mk[i, j]
            b[n + i, n + j] = -md[i, j]
        b[n + i, 3 * n] = sum(minv[i, r] * mpf(f[r]) for r in range(n))
        b[n + i, 3 * n + 1] = mpf(AMP) * sum(minv[i, r] * mpf(g[r]) for r in range(n))
    b[3 * n + 1, 3 * n + 2] = mpf(OMEGA)
    b[3 * n + 2, 3 * n + 1] = -mpf(OMEGA)
    z0 = matrix(dim, 1)
    for i in range(n):
        z0[i] = mpf(q0[i])
        z0[n + i] = mpf(v0[i])
    z0[3 * n] = 1
    th = mpf(OMEGA) * mpf(T0)
    z0[3 * n + 1] = sin(th)
    z0[3 * n + 2] = cos(th)
    z = expm(b * mpf(tau)) * z0
    return [z[2 * n + i] for i in range(n)]


def main():
    rows = ["case,c,tau," + ",".join(f"w_{i}" for i in range(3))]
    for name in ["one", "chain"]:
        for c in CS:
            for tau in TAUS:
                w = integral(name, c, tau)
                rows.append(",".join([name, repr(c), repr(tau)] + [mp.nstr(x, 25, min_fixed=0, max_fixed=0) for x in w]))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "position_integral.csv")
    with open(out, "w") as fh:
        fh.write("\n".join(rows) + "\n")
    print(f"{len(rows) - 1} rows to {out}")


if __name__ == "__main__":
    main()
