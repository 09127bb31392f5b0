#!/usr/bin/python3
"""Siconos's Moreau–Jean integrator on small systems: the numbers that
`crates/schemes/tests/it/siconos.rs` compares `moreau-jean(θ,e,γ)` and
`moreau-jean-projected(θ,e,γ)` with, step by step.

Needs Siconos's Python bindings (Debian: `apt install python3-siconos`, 4.4.0
when these numbers were written; run with the system's /usr/bin/python3).
Writes data/siconos/moreau-jean.csv, data/siconos/moreau-jean-projected.csv
and data/siconos/moreau-jean-combined.csv
(every digit: `repr` of each double):

    /usr/bin/python3 tests/siconos/moreau_jean.py

The systems (the Rust test builds the same ones; change both together):
`M q'' + C q' + K q = F` with three dofs, a consistent-mass-like `M`, a
spring chain `K`, Rayleigh damping `C = a M + b K` (a = 0.1, b = 0.05, or
none), a steady load `F` (`[-2, 0.1, 1.5]`; `[-2, -0.5, -0.5]` with one contact) (Siconos's `θ F(t_{k+1}) + (1 − θ) F(t_k)` and our
exact mean agree only for a steady load), and unilateral contacts
`q_0 >= lo` (restitution e_0) and, in the two-contact cases, `q_2 <= hi`
(e_2). Siconos: `LagrangianLinearTIDS`, one `LagrangianLinearTIR` per
contact (`y = H q + b >= 0`), `NewtonImpactNSL(e)`, `MoreauJeanOSI(θ, γ)`
(activation `y_k + γ h ẏ_k <= 0`), `LCP()` (Lemke), `TimeStepping`.
Columns: case, theta, gamma, step, t, q0..q2, v0..v2, p0, p2 (the
impulses of the contacts over the step; p2 is 0 in one-contact cases).

The projected runs: the same systems and (θ, γ) under
`MoreauJeanDirectProjectionOSI(θ, γ)`, `TimeSteppingDirectProjection` and
`MLCPProjectOnConstraints()` (its defaults: no mass normalisation, α = 1,
the enumerative MLCP solver; the index set's thresholds 1e-7, the
projection's tolerance 1e-8, at most 10 projections a step); one more
column, projections (the projection iterations of the step); and one more
system, PROJECTED_EXTRA.

The combined runs (data/siconos/moreau-jean-combined.csv): the same
systems and PROJECTED_EXTRA, one run per θ (γ plays no part; written as
0), under `MoreauJeanCombinedProjectionOSI(θ)`,
`TimeSteppingCombinedProjection` and `MLCPProjectOnConstraints()` (its
defaults: the contacts of index set 2 projected as equalities `y = 0`,
tolerance 1e-8, at most 50 projections and 50 index-set passes a step);
two more columns, projections (the projection iterations of the step,
cumulated over its passes) and passes (the step's index-set passes).
"""

import csv
import os
import sys

import numpy as np
import siconos.kernel as sk

M = np.array([[2.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 2.0]]) / 6.0
K = np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]) * 30.0
F = np.array([-2.0, 0.1, 1.5])
F_DOWN = np.array([-2.0, -0.5, -0.5])
Q0 = np.array([0.05, 0.0, -0.02])
V0 = np.array([-1.0, 0.3, 0.8])
LO, HI = 0.0, 0.08
H_STEP, STEPS = 0.01, 300

# (name, contacts ((dof, side, bound, e), ...), damped, load)
CASES = [
    ("one-contact", ((0, "lo", LO, 0.5),), False, F_DOWN),
    ("two-contacts", ((0, "lo", LO, 0.5), (2, "hi", HI, 0.8)), False, F),
    ("two-contacts-damped", ((0, "lo", LO, 0.0), (2, "hi", HI, 0.8)), True, F),
]
SCHEMES = [(0.5, 0.5), (0.5, 1.0), (0.75, 0.5), (1.0, 0.0), (1.0, 1.0)]
# The projected runs only, one more: twice the load, θ = ½, γ = 0, where
# contacts stay in the index set while their predicted gap is open and
# they approach (Siconos's hysteresis: 50 such steps).
PROJECTED_EXTRA = [("two-contacts-loaded", ((0, "lo", LO, 0.5), (2, "hi", HI, 0.8)), False, 2.0 * F, [(0.5, 0.0)])]


def run(contacts, damped, load, theta, gamma, projected=False, combined=False):
    c = 0.1 * M + 0.05 * K if damped else np.zeros((3, 3))
    ds = sk.LagrangianLinearTIDS(Q0.copy(), V0.copy(), M, K, c)
    ds.setFExtPtr(load.copy())
    nsds = sk.NonSmoothDynamicalSystem(0.0, H_STEP * STEPS)
    nsds.insertDynamicalSystem(ds)
    inters = []
    for dof, side, bound, e in contacts:
        h = np.zeros((1, 3))
        # lower: y = q - lo >= 0; upper: y = hi - q >= 0.
        h[0, dof] = 1.0 if side == "lo" else -1.0
        b = np.array([-bound if side == "lo" else bound])
        inter = sk.Interaction(sk.NewtonImpactNSL(e), sk.LagrangianLinearTIR(h, b))
        nsds.link(inter, ds)
        inters.append(inter)
    td = sk.TimeDiscretisation(0.0, H_STEP)
    if combined:
        # Its constructor takes θ only: no γ (the index set is decided on
        # the step's positions, not on a prediction).
        osi = sk.MoreauJeanCombinedProjectionOSI(theta)
        sim = sk.TimeSteppingCombinedProjection(nsds, td, osi, sk.LCP(), sk.MLCPProjectOnConstraints())
    elif projected:
        osi = sk.MoreauJeanDirectProjectionOSI(theta, gamma)
        sim = sk.TimeSteppingDirectProjection(nsds, td, osi, sk.LCP(), sk.MLCPProjectOnConstraints())
    else:
        osi = sk.MoreauJeanOSI(theta, gamma)
        sim = sk.TimeStepping(nsds, td, osi, sk.LCP())
    rows = [(0, 0.0, ds.q().copy(), ds.velocity().copy(), [0.0, 0.0], (0, 0) if combined else 0)]
    k = 0
    while sim.hasNextEvent() and k < STEPS:
        sim.computeOneStep()
        k += 1
        p = [float(i.lambda_(1)[0]) for i in inters]
        # p per contact, the second column for dof 2's contact.
        pp = [p[0], p[1] if len(p) > 1 else 0.0]
        nproj = sim.nbProjectionIteration() if projected else 0
        if combined:
            nproj = (sim.nbCumulatedProjectionIteration(), sim.nbIndexSetsIteration())
        rows.append((k, sim.nextTime(), ds.q().copy(), ds.velocity().copy(), pp, nproj))
        sim.nextStep()
    return rows


def main():
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    for file, projected in [("moreau-jean.csv", False), ("moreau-jean-projected.csv", True)]:
        out = os.path.join(root, "data", "siconos", file)
        os.makedirs(os.path.dirname(out), exist_ok=True)
        with open(out, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["case", "theta", "gamma", "step", "t", "q0", "q1", "q2", "v0", "v1", "v2", "p0", "p2"] + (["projections"] if projected else []))
            cases = [c + (SCHEMES,) for c in CASES] + (PROJECTED_EXTRA if projected else [])
            for name, contacts, damped, load, schemes in cases:
                for theta, gamma in schemes:
                    for k, t, q, v, p, nproj in run(contacts, damped, load, theta, gamma, projected):
                        row = [name, repr(theta), repr(gamma), k, repr(float(t))] + [repr(float(x)) for x in q] + [repr(float(x)) for x in v] + [repr(x) for x in p]
                        w.writerow(row + ([nproj] if projected else []))
        print(f"wrote {out} (Siconos {getattr(sk, '__version__', '4.x')}, Python {sys.version.split()[0]})")
    out = os.path.join(root, "data", "siconos", "moreau-jean-combined.csv")
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["case", "theta", "gamma", "step", "t", "q0", "q1", "q2", "v0", "v1", "v2", "p0", "p2", "projections", "passes"])
        cases = [c + (SCHEMES,) for c in CASES] + PROJECTED_EXTRA
        for name, contacts, damped, load, schemes in cases:
            # γ plays no part: one run per θ (written with γ = 0).
            for theta in sorted({th for th, _ in schemes}):
                for k, t, q, v, p, (nproj, passes) in run(contacts, damped, load, theta, 0.0, combined=True):
                    row = [name, repr(theta), repr(0.0), k, repr(float(t))] + [repr(float(x)) for x in q] + [repr(float(x)) for x in v] + [repr(x) for x in p]
                    w.writerow(row + [nproj, passes])
    print(f"wrote {out} (Siconos {getattr(sk, '__version__', '4.x')}, Python {sys.version.split()[0]})")


if __name__ == "__main__":
    main()
