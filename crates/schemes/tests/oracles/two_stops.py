#!/usr/bin/env python3
"""Independent high-precision oracle: a free P1 bar between two unilateral stops.

Problem
-------
P1 finite elements on [0, 1], wave speed 1, density 1, 3 elements (h = 1/3),
both ends free (no Dirichlet condition).  Nodes u0..u3.
    K = (1/h) [[1,-1,0,0],[-1,2,-1,0],[0,-1,2,-1],[0,0,-1,1]]
    M_std    = (h/6) [[2,1,0,0],[1,4,1,0],[0,1,4,1],[0,0,1,2]]   (consistent)
    M_lumped = h diag(1/2, 1, 1, 1/2)
No load, no damping.  u(0) = 0, u'(0) = -0.5 at every node.
Two stops (unilateral lower bounds): u0 >= -0.05 and u3 >= -0.05.
Newton's impact law, restitution e = 1/2: at an impact the post-impact velocity
is v+ = v- + M^{-1} C^T lambda with C v+ = -e C v- on the impacting contacts.

Reduction
---------
The data are mirror symmetric, so u = P q with q = (a, b), u = (a, b, b, a),
P = [[1,0],[0,1],[0,1],[1,0]], Ms = P^T M P, Ks = P^T K P, one contact a >= g
(g = -0.05), impulse along Ms^{-1} e_a, v_a+ = -e v_a-.  The script checks that
this is legitimate on the full 4-dof system: the Delassus W = C M^{-1} C^T
(2x2) with equal impulses solves the two-contact Newton law with lambda >= 0,
reproduces the reduced impulse, and a direct 4-dof simulation (both contacts,
2x2 solve at each impact) gives the same first impact times.

Method
------
Between events the motion is the exact free flow of (Ms, Ks): generalized
eigenpairs (Cholesky + mp.eigsy at the working precision; one rigid mode,
w = 0, and one elastic mode).  The flow is written relative to the state
(q0, v0) at the start of the flight so that tiny flights (chatter) keep full
relative accuracy:
    q(s) = q0 + s v0 + s^2/2 acc0 + sum_k phi_k [SM(w s)/w d_k + CM(w s)/w^2 (-w^2 c_k)]
    v(s) = v0 + s acc0 + sum_k phi_k [(cos(w s)-1) d_k + SM(w s)/w (-w^2 c_k)]
with c = Phi^T Ms q0, d = Phi^T Ms v0, acc0 = -Ms^{-1} Ks q0,
SM(x) = sin x - x, CM(x) = 1 - cos x - x^2/2 (Taylor series for small x).
Next impact = first root s > 0 of a(s) - g.  a(s) = alpha + beta s + E cos ws
+ F sin ws, so its critical points (v_a = 0) are found in closed form; between
two consecutive critical points a is monotone.  The first critical point where
a < g brackets the first crossing (no crossing can be missed: this is the
grazing check; the smallest gap a - g at a local minimum of a before each
root is recorded and printed), then bisection to full precision.
Chatter: impacts are iterated until the impact speed is < 1e-25 (at 40 digits;
1e-40 in the 60-digit check) times the first one of the sequence; t_inf = t_n + tau_n r/(1-r), r = tau_n/tau_{n-1}
(geometric tail; r -> e is checked).  Tail error estimate: the larger of the change of
that estimate when r is taken from the previous pair and the change vs n-1.
The state at t_inf: last post-impact state flowed over the tail, plus the tail
impulse (1+e) e |v_n-| / ((1-e) W) along Ms^{-1} e_a, then a = g, v_a = 0.
Held phase: a = g fixed, b'' = -(Ks_bb b + Ks_ba g)/Ms_bb (harmonic about
b = g since Ks_ba = -Ks_bb); contact force r = (Ms q'' + Ks q)_a =
(Ks_ab - Ms_ab w_h^2)(b - g), must be >= 0 (also checked against the
acceleration LCP at t_inf: r = -acc_a_free / (Ms^{-1})_aa).  Release at the
first zero of r (closed form), then free flight from there, and the same
machinery up to T_END = 1.  After a release the script prints the rigid
velocity V and the elastic amplitude A of a: once t - t_rel > 2 A / V no
impact is possible any more (no load).

Output
------
two_stops_std.csv and two_stops_lumped.csv (next to this script):
t,kind,velocity_before,velocity_after with kind impact/accumulation/release,
25 significant digits; velocities are those of the contact dof a (= u0 = u3).
Only events with t <= T_END = 1 are written.
Impacts are listed individually while their speed is >= 1e-6 times the first
impact speed of their chatter sequence; then one accumulation row (velocity
before 0, after 0); release rows have velocities 0,0.

Run
---
    python3 two_stops.py            # 40 digits, writes the CSVs, prints a report
    python3 two_stops.py --check    # also reruns at 60 digits (iterating to 1e-40) and prints agreement
    python3 two_stops.py --beyond=3 # also prints the events in (1, 3] (not written to the CSVs)
Needs mpmath (1.3).  Runs in well under 2 minutes.
"""

import sys
import os
from mpmath import mp, mpf, matrix

E_REST = mpf(1) / 2
T_END = 1


def mats(kind):
    h = mpf(1) / 3
    K = matrix([[1, -1, 0, 0], [-1, 2, -1, 0], [0, -1, 2, -1], [0, 0, -1, 1]]) / h
    if kind == "std":
        M = matrix([[2, 1, 0, 0], [1, 4, 1, 0], [0, 1, 4, 1], [0, 0, 1, 2]]) * h / 6
    else:
        M = matrix([[mpf(1) / 2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, mpf(1) / 2]]) * h
    return M, K


def reduce(M, K):
    P = matrix([[1, 0], [0, 1], [0, 1], [1, 0]])
    return P.T * M * P, P.T * K * P


def SM(x):
    """sin x - x, accurate for small x."""
    if abs(x) > mpf(1) / 2:
        return mp.sin(x) - x
    term = x
    s = mpf(0)
    k = 1
    x2 = x * x
    while True:
        term = -term * x2 / ((2 * k) * (2 * k + 1))
        s += term
        if abs(term) <= abs(s) * mp.eps * mpf(10) ** -5 or term == 0:
            return s
        k += 1


def CM(x):
    """1 - cos x - x^2/2, accurate for small x."""
    if abs(x) > mpf(1) / 2:
        return 1 - mp.cos(x) - x * x / 2
    x2 = x * x
    term = x2 / 2  # x^2/2!, sign +; series: sum_{k>=2} (-1)^{k+1} x^{2k}/(2k)!
    s = mpf(0)
    k = 1
    while True:
        term = -term * x2 / ((2 * k + 1) * (2 * k + 2))
        k += 1
        s += term
        if abs(term) <= abs(s) * mp.eps * mpf(10) ** -5 or term == 0:
            return s


class Flow:
    """Exact free flow of M q'' + K q = 0 (symmetric positive M, semi-definite K)."""

    def __init__(self, M, K):
        n = M.rows
        self.n = n
        self.M = M
        self.K = K
        self.Minv = M ** -1
        L = mp.cholesky(M)
        Li = L ** -1
        A = Li * K * Li.T
        A = (A + A.T) / 2
        ev, Y = mp.eigsy(A)
        Phi = Li.T * Y  # mass normalized: Phi^T M Phi = I
        self.w = []
        self.phi = []
        tol = mpf(10) ** (-mp.dps // 2)
        for k in range(n):
            lam = ev[k]
            w = mpf(0) if abs(lam) < tol else mp.sqrt(lam)
            self.w.append(w)
            self.phi.append(Phi[:, k])
        self.A = self.Minv * K

    def modal(self, q0, v0):
        c = [(self.phi[k].T * self.M * q0)[0] for k in range(self.n)]
        d = [(self.phi[k].T * self.M * v0)[0] for k in range(self.n)]
        return c, d

    def state(self, q0, v0, s):
        """(q(s), v(s)) from (q0, v0) at s = 0, relative form (see module doc)."""
        c, d = self.modal(q0, v0)
        acc0 = -(self.A * q0)
        q = q0 + v0 * s + acc0 * (s * s / 2)
        v = v0 + acc0 * s
        for k in range(self.n):
            w = self.w[k]
            if w == 0:
                continue
            x = w * s
            sm = SM(x)
            q += self.phi[k] * (sm / w * d[k] - CM(x) * c[k])
            v += self.phi[k] * ((-2 * mp.sin(x / 2) ** 2) * d[k] - sm * w * c[k])
        return q, v

    def disp_fn(self, q0, v0, i):
        """s -> q_i(s) - q0_i (relative accuracy also for tiny s); modal data computed once."""
        c, d = self.modal(q0, v0)
        acc0 = -(self.A * q0)
        vi, ai = v0[i], acc0[i]
        el = [(self.w[k], self.phi[k][i] * d[k], self.phi[k][i] * c[k]) for k in range(self.n) if self.w[k] != 0]

        def f(s):
            r = vi * s + ai * (s * s / 2)
            for (w, pd, pc) in el:
                x = w * s
                r += SM(x) / w * pd - CM(x) * pc
            return r
        return f

    def crit_points(self, q0, v0, i, S):
        """Closed-form zeros s in (0, S] of v_i(s) (needs at most one elastic mode)."""
        c, d = self.modal(q0, v0)
        r = mpf(0)
        E = mpf(0)
        F = mpf(0)
        el = [k for k in range(self.n) if self.w[k] != 0]
        assert len(el) == 1, "closed-form critical points need one elastic mode"
        for k in range(self.n):
            if self.w[k] == 0:
                r += self.phi[k][i] * d[k]
        k = el[0]
        w = self.w[k]
        E = self.phi[k][i] * d[k]
        F = -self.phi[k][i] * w * c[k]
        R = mp.sqrt(E * E + F * F)
        out = []
        if R == 0 or abs(r) > R:
            return out
        phase = mp.atan2(F, E)
        ac = mp.acos(-r / R)
        eps = mpf(10) ** (-mp.dps + 4)
        for base in (phase + ac, phase - ac):
            # w s = base + 2 pi m
            m = mp.ceil((-base) / (2 * mp.pi)) - 1
            while True:
                s = (base + 2 * mp.pi * m) / w
                if s > S:
                    break
                if s > eps:
                    out.append(s)
                m += 1
        return sorted(out)


def next_impact(fl, q0, v0, i, g, S):
    """First s in (0, S] with q_i(s) = g. Returns (s, min_margin) or (None, min_margin)."""
    gap0 = q0[i] - g
    disp = fl.disp_fn(q0, v0, i)

    def d(s):
        return gap0 + disp(s)

    pts = fl.crit_points(q0, v0, i, S) + [mpf(S)]
    lo = mpf(0)
    dlo = gap0
    margin = None
    for p in pts:
        dp = d(p)
        if dp < 0:
            hi = p
            # a is monotone on [lo, hi]; d(lo) >= 0 (lo = 0 or a local extremum above g)
            for _ in range(int(mp.prec * 1.1) + 20):
                mid = (lo + hi) / 2
                if mid == lo or mid == hi:
                    break
                if d(mid) < 0:
                    hi = mid
                else:
                    lo = mid
            return (lo + hi) / 2, margin
        if p != S and dp < dlo and (margin is None or dp < margin):
            # a decreased on [lo, p]: p is a local minimum of a above g (grazing check)
            margin = dp
        lo = p
        dlo = dp
    return None, margin


def impact(fl, q, v, i, e):
    vm = v[i]
    W = fl.Minv[i, i]
    lam = -(1 + e) * vm / W
    vp = v + fl.Minv[:, i] * lam
    vp[i] = -e * vm
    return vp, lam


def simulate(kind, tail_rel, list_rel, log, t_end=T_END):
    M4, K4 = mats(kind)
    Ms, Ks = reduce(M4, K4)
    fl = Flow(Ms, Ks)
    g = mpf(-5) / 100
    e = E_REST
    t = mpf(0)
    q = matrix([0, 0])
    v = matrix([mpf(-1) / 2, mpf(-1) / 2])
    rows = []
    info = {"sequences": []}
    seq = None
    while t < t_end:
        s, margin = next_impact(fl, q, v, 0, g, t_end - t)
        if s is None:
            break
        q, v = fl.state(q, v, s)
        t = t + s
        q[0] = g
        vm = v[0]
        vp, lam = impact(fl, q, v, 0, e)
        v = vp
        if seq is None:
            seq = {"times": [], "vm": [], "margins": [], "first_speed": abs(vm)}
            info["sequences"].append(seq)
        seq["times"].append(t)
        seq["vm"].append(vm)
        seq["margins"].append(margin)
        if abs(vm) >= list_rel * seq["first_speed"]:
            rows.append((t, "impact", vm, vp[0]))
        if abs(vm) < tail_rel * seq["first_speed"]:
            # accumulation
            ts = seq["times"]
            tau = [ts[k] - ts[k - 1] for k in range(1, len(ts))]
            r1 = tau[-1] / tau[-2]
            r2 = tau[-2] / tau[-3]
            T = tau[-1] * r1 / (1 - r1)
            T2 = tau[-1] * r2 / (1 - r2)
            Tprev = tau[-2] * r2 / (1 - r2)
            tinf = t + T
            seq["tinf"] = tinf
            seq["tail"] = T
            seq["tail_err"] = max(abs(T - T2), abs((ts[-2] + Tprev) - tinf))
            seq["ratios"] = [tau[k] / tau[k - 1] for k in range(1, len(tau))]
            W = fl.Minv[0, 0]
            qi, vi = fl.state(q, v, T)
            vi = vi + fl.Minv[:, 0] * ((1 + e) * e * abs(vm) / ((1 - e) * W))
            seq["va_at_tinf_before_zeroing"] = vi[0]
            qi[0] = g
            vi[0] = 0
            q, v, t = qi, vi, tinf
            rows.append((tinf, "accumulation", mpf(0), mpf(0)))
            # held force from the acceleration LCP: free acc of a, r = -acc_a / W
            acc = -(fl.A * q)
            r_lcp = -acc[0] / W
            # held phase closed form
            wh2 = Ks[1, 1] / Ms[1, 1]
            wh = mp.sqrt(wh2)
            coef = Ks[0, 1] - Ms[0, 1] * wh2
            y0 = q[1] - g
            y1 = v[1]
            r_held = coef * y0
            seq["held_force"] = r_held
            seq["held_force_lcp"] = r_lcp
            seq["b_at_tinf"] = q[1]
            seq["vb_at_tinf"] = v[1]
            if r_lcp < 0:
                log("  contact force at t_inf negative: no held phase")
                seq = None
                continue
            # y(t) = y0 cos wh t + y1/wh sin wh t = 0, first t > 0
            # solve tan(wh t) = -y0 wh / y1 for the first t > 0
            base = mp.atan(-y0 * wh / y1) if y1 != 0 else mp.pi / 2
            while base <= 0:
                base += mp.pi
            trel = base / wh
            t_rel = tinf + trel
            # after the release: q = (g, g), v = (0, vb); rigid drift vs elastic amplitude
            b_r = g + y0 * mp.cos(wh * trel) + y1 / wh * mp.sin(wh * trel)
            vb_r = -y0 * wh * mp.sin(wh * trel) + y1 * mp.cos(wh * trel)
            qr, vr = matrix([g, b_r]), matrix([mpf(0), vb_r])
            one = matrix([1, 1])
            Vr = (one.T * Ms * vr)[0] / (one.T * Ms * one)[0]
            cr, dr = fl.modal(qr, vr)
            ke = [k for k in range(2) if fl.w[k] != 0][0]
            amp = abs(fl.phi[ke][0]) * mp.sqrt(cr[ke] ** 2 + (dr[ke] / fl.w[ke]) ** 2)
            seq["after_release"] = (Vr, amp)
            seq["release"] = t_rel
            if t_rel >= t_end:
                seq["release_beyond_end"] = True
                break
            b = g + y0 * mp.cos(wh * trel) + y1 / wh * mp.sin(wh * trel)
            vb = -y0 * wh * mp.sin(wh * trel) + y1 * mp.cos(wh * trel)
            seq["release_residual_y"] = b - g
            seq["vb_release"] = vb
            q = matrix([g, g])
            v = matrix([mpf(0), vb])
            t = t_rel
            rows.append((t_rel, "release", mpf(0), mpf(0)))
            seq = None
    info["rows"] = rows
    info["Ms"], info["Ks"], info["flow"] = Ms, Ks, fl
    info["end_state"] = (t, q, v)
    return info


def full_check(kind, nimp, log):
    """4-dof system, both contacts, direct simulation of the first nimp impacts."""
    M, K = mats(kind)
    fl = Flow(M, K)
    g = mpf(-5) / 100
    e = E_REST
    C = [0, 3]
    W = matrix(2, 2)
    for i in range(2):
        for j in range(2):
            W[i, j] = fl.Minv[C[i], C[j]]
    t = mpf(0)
    q = matrix([0, 0, 0, 0])
    v = matrix([mpf(-1) / 2] * 4)
    times = []
    lams = []
    for _ in range(nimp):
        # sample then bisect (cross-check only; flights here are not tiny)
        S = T_END - t
        N = 1000

        d0, d3 = fl.disp_fn(q, v, 0), fl.disp_fn(q, v, 3)

        def d(s, i):
            return q[i] - g + (d0(s) if i == 0 else d3(s))

        lo = mpf(0)
        hit = None
        for k in range(1, N + 1):
            s = S * k / N
            if d(s, 0) < 0 or d(s, 3) < 0:
                hit = s
                break
            lo = s
        if hit is None:
            break
        hi = hit
        for _ in range(int(mp.prec * 1.1) + 20):
            mid = (lo + hi) / 2
            if min(d(mid, 0), d(mid, 3)) < 0:
                hi = mid
            else:
                lo = mid
        s = (lo + hi) / 2
        q, v = fl.state(q, v, s)
        t += s
        asym = max(abs(q[0] - q[3]), abs(q[1] - q[2]), abs(v[0] - v[3]), abs(v[1] - v[2]))
        q[0] = g
        q[3] = g
        vc = matrix([v[0], v[3]])
        lam = W ** -1 * (-(1 + e) * vc)
        v = v + fl.Minv[:, 0] * lam[0] + fl.Minv[:, 3] * lam[1]
        times.append(t)
        lams.append((lam[0], lam[1], asym))
    return W, times, lams


def fmt(x, n=25):
    return mp.nstr(x, n, min_fixed=-mp.inf, max_fixed=mp.inf) if x != 0 else "0"


def fmt_row(x):
    if x == 0:
        return "0"
    return mp.nstr(x, 25, strip_zeros=False)


def run(dps, tail_rel, write, log, do_full=True):
    mp.dps = dps
    res = {}
    for kind in ("std", "lumped"):
        info = simulate(kind, tail_rel, mpf(10) ** -6, log)
        res[kind] = info
        log("=== %s (dps %d) ===" % (kind, dps))
        Ms, Ks, fl = info["Ms"], info["Ks"], info["flow"]
        log("Ms = %s" % [[fmt(Ms[i, j], 12) for j in range(2)] for i in range(2)])
        log("Ks = %s" % [[fmt(Ks[i, j], 12) for j in range(2)] for i in range(2)])
        log("elastic w = %s" % [fmt(w, 20) for w in fl.w])
        for si, seq in enumerate(info["sequences"]):
            n = len(seq["times"])
            log(" sequence %d: %d impacts, first at %s, speed %s" % (si, n, fmt(seq["times"][0]), fmt(abs(seq["vm"][0]))))
            for k in range(min(6, n)):
                log("   impact %d t=%s v-=%s margin=%s" % (k + 1, fmt(seq["times"][k]), fmt(seq["vm"][k], 20),
                                                        fmt(seq["margins"][k], 6) if seq["margins"][k] is not None else "-"))
            mins = [m for m in seq["margins"] if m is not None]
            if mins:
                log("   grazing check: smallest gap a - g at a local minimum of a before an impact: %s" % fmt(min(mins), 6))
            else:
                log("   grazing check: no flight has a local minimum of a before its impact (a rises then falls monotonically onto the stop)")
            if "tinf" in seq:
                rat = seq["ratios"]
                log("   tau_k/tau_(k-1) - e, k = 2..5 and last 3: %s ... %s" % ([fmt(x - E_REST, 3) for x in rat[:4]], [fmt(x - E_REST, 3) for x in rat[-3:]]))
                log("   t_inf = %s  tail %s  tail err est %s" % (fmt(seq["tinf"], 30), fmt(seq["tail"], 5), fmt(seq["tail_err"], 3)))
                log("   v_a at t_inf before zeroing (should be ~0): %s" % fmt(seq["va_at_tinf_before_zeroing"], 3))
                log("   b(t_inf)=%s v_b(t_inf)=%s" % (fmt(seq["b_at_tinf"], 25), fmt(seq["vb_at_tinf"], 25)))
                log("   held force: closed form %s, LCP %s" % (fmt(seq["held_force"], 20), fmt(seq["held_force_lcp"], 20)))
            if "release" in seq:
                Vr, amp = seq["after_release"]
                log("   after release: rigid velocity %s, elastic amplitude of a %s: a > g for ever once t - t_rel > 2 amp / V = %s"
                    % (fmt(Vr, 10), fmt(amp, 10), fmt(2 * amp / Vr, 10)))
                if seq.get("release_beyond_end"):
                    log("   release t=%s (after the horizon: not in the CSV)" % fmt(seq["release"], 30))
                else:
                    log("   release t=%s (y residual %s), v_b=%s" % (fmt(seq["release"], 30), fmt(seq["release_residual_y"], 3), fmt(seq["vb_release"], 20)))
        t, q, v = info["end_state"]
        log(" rows: %d" % len(info["rows"]))
        if write:
            path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "two_stops_%s.csv" % kind)
            with open(path, "w") as f:
                f.write("t,kind,velocity_before,velocity_after\n")
                for (tt, kd, vb, va) in info["rows"]:
                    f.write("%s,%s,%s,%s\n" % (fmt_row(tt), kd, fmt_row(vb), fmt_row(va)))
            log(" wrote %s" % path)
        if do_full:
            W, times, lams = full_check(kind, 6, log)
            log(" 4-dof check: W = C M^-1 C^T = [[%s, %s], [%s, %s]]" % (fmt(W[0, 0], 15), fmt(W[0, 1], 15), fmt(W[1, 0], 15), fmt(W[1, 1], 15)))
            Wr = fl.Minv[0, 0]
            log("   reduced (Ms^-1)_aa = %s; W00 + W03 = %s; 2 (Ms^-1)_aa - (W00+W03) = %s" %
                (fmt(Wr, 15), fmt(W[0, 0] + W[0, 1], 15), fmt(2 * Wr - W[0, 0] - W[0, 1], 3)))
            seq0 = info["sequences"][0]
            for k, tt in enumerate(times):
                l0, l1, asym = lams[k]
                log("   4-dof impact %d t=%s |dt vs 2-dof|=%s lambda=(%s, %s) asym=%s" %
                    (k + 1, fmt(tt, 20), fmt(abs(tt - seq0["times"][k]), 3), fmt(l0, 10), fmt(l1, 10), fmt(asym, 3)))
    return res


def main():
    import time
    t0 = time.time()
    log = print
    res40 = run(40, mpf(10) ** -25, True, log)
    if "--check" in sys.argv:
        quiet = []
        res60 = run(60, mpf(10) ** -40, False, quiet.append, do_full=False)
        mp.dps = 60
        print("=== 40 vs 60 digits (60-digit run iterates to 1e-40) ===")
        for kind in ("std", "lumped"):
            a, b = res40[kind], res60[kind]
            for si, (sa, sb) in enumerate(zip(a["sequences"], b["sequences"])):
                m = min(len(sa["times"]), len(sb["times"]))
                dt = max(abs(sa["times"][k] - sb["times"][k]) for k in range(m))
                dv = max(abs(sa["vm"][k] - sb["vm"][k]) for k in range(m))
                print("%s seq %d: max |dt| impacts %s, max |dv-| %s" % (kind, si, fmt(dt, 3), fmt(dv, 3)))
                for key in ("tinf", "release"):
                    if key in sa and key in sb:
                        print("  %s: 40d %s 60d %s diff %s" % (key, fmt(sa[key], 30), fmt(sb[key], 30), fmt(abs(sa[key] - sb[key]), 3)))
            ra, rb = a["rows"], b["rows"]
            # compare the CSV rows (60-digit run lists the same rows)
            n = min(len(ra), len(rb))
            mx = mpf(0)
            for k in range(n):
                if ra[k][1] == rb[k][1]:
                    mx = max(mx, abs(ra[k][0] - rb[k][0]))
            print("  rows 40d %d, 60d %d, max |dt| over common rows %s" % (len(ra), len(rb), fmt(mx, 3)))
    for arg in sys.argv:
        if arg.startswith("--beyond="):
            mp.dps = 40
            te = mpf(arg.split("=")[1])
            print("=== events after t = 1 up to t = %s (40 digits; not in the CSVs) ===" % te)
            for kind in ("std", "lumped"):
                info = simulate(kind, mpf(10) ** -25, mpf(10) ** -6, lambda *_: None, t_end=te)
                for (tt, kd, vb, va) in info["rows"]:
                    if tt > 1:
                        print("  %s %s %s v-=%s v+=%s" % (kind, kd, fmt(tt, 25), fmt(vb, 15), fmt(va, 15)))
                for seq in info["sequences"]:
                    if seq["times"][0] > 1:
                        print("  %s sequence from %s: %d impacts%s" % (kind, fmt(seq["times"][0], 15), len(seq["times"]),
                              (", t_inf %s" % fmt(seq["tinf"], 25)) if "tinf" in seq else ""))
    print("elapsed %.1f s" % (time.time() - t0))


if __name__ == "__main__":
    main()
