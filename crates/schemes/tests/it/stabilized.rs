//! The contact-stabilized Newmark scheme (Deuflhard, Krause, Ertel 2008;
//! docs/theory.md §4.6.6) against a dense transcription of the paper's step
//! written here: the predictor `U + τV` projected onto the admissible set in
//! the mass norm, the trapezoidal step's constrained minimisation, the
//! velocity `V + 2/τ (U^{n+1} − U_pred)`. Both box-constrained quadratic
//! programs are solved here by brute force — every active set tried, the
//! one that satisfies the KKT conditions kept — with dense Gaussian
//! elimination, independently of the crate's contact solves. Random small
//! systems with damping, a time-dependent load, gaps and two contacts
//! (one two-sided), step by step to 1e-12; and the paper's claim that the
//! energy never grows without damping and load.

use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, ContactStabilized, Dynamics, Forcing, Initial, SchemeSpec, SplitMix64, Stepper, TimeProfile};

pub(crate) type Dense = Vec<Vec<f64>>;

pub(crate) fn mv(a: &Dense, x: &[f64]) -> Vec<f64> {
    a.iter().map(|r| r.iter().zip(x).map(|(a, x)| a * x).sum()).collect()
}

pub(crate) fn dense(b: &SymBand) -> Dense {
    let n = b.n();
    (0..n).map(|i| (0..n).map(|j| if i.abs_diff(j) <= b.half_bandwidth() { b.get(i.max(j), i.min(j)) } else { 0.0 }).collect()).collect()
}

/// Gaussian elimination with partial pivoting.
pub(crate) fn solve(mut a: Dense, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            for k in c..n {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        x[r] = (b[r] - (r + 1..n).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
    }
    x
}

/// `argmin ½ (w − y)ᵀ H (w − y)` over `lo_i <= w_{c_i} <= hi_i`, by trying
/// every active set (free, at lo, at hi per contact); the multipliers
/// `μ_i = (H (w − y))_{c_i}`.
fn box_qp(h: &Dense, y: &[f64], cons: &[(usize, f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    let n = y.len();
    let k = cons.len();
    let hy = mv(h, y);
    'sets: for code in 0..3usize.pow(k as u32) {
        let status: Vec<usize> = (0..k).map(|i| code / 3usize.pow(i as u32) % 3).collect();
        let mut fixed: Vec<Option<f64>> = vec![None; n];
        for (&(c, lo, hi), &s) in cons.iter().zip(&status) {
            fixed[c] = match s {
                0 => None,
                1 if lo.is_finite() => Some(lo),
                2 if hi.is_finite() => Some(hi),
                _ => continue 'sets,
            };
        }
        let free: Vec<usize> = (0..n).filter(|&i| fixed[i].is_none()).collect();
        let hf: Dense = free.iter().map(|&i| free.iter().map(|&j| h[i][j]).collect()).collect();
        let rf: Vec<f64> = free.iter().map(|&i| hy[i] - (0..n).filter_map(|j| fixed[j].map(|x| h[i][j] * x)).sum::<f64>()).collect();
        let wf = if free.is_empty() { Vec::new() } else { solve(hf, rf) };
        let mut w: Vec<f64> = fixed.iter().map(|x| x.unwrap_or(0.0)).collect();
        for (&i, x) in free.iter().zip(&wf) {
            w[i] = *x;
        }
        let d: Vec<f64> = w.iter().zip(y).map(|(w, y)| w - y).collect();
        let r = mv(h, &d);
        let scale = 1.0 + hy.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let tol = 1e-12 * scale;
        let mu: Vec<f64> = cons.iter().map(|&(c, _, _)| r[c]).collect();
        let ok = cons.iter().zip(&status).zip(&mu).all(|((&(c, lo, hi), &s), &m)| match s {
            0 => w[c] >= lo - 1e-12 && w[c] <= hi + 1e-12,
            1 => m >= -tol,
            _ => m <= tol,
        });
        if ok {
            return (w, mu);
        }
    }
    panic!("no active set satisfies the KKT conditions");
}

/// A random 4-dof chain: a tridiagonal SPD mass (lumped if asked), springs
/// to a wall, optional Rayleigh-like damping, a steady and a sine load.
pub(crate) fn system(rng: &mut SplitMix64, lumped: bool, damped: bool, two: bool) -> (Dynamics, Initial) {
    let n = 4;
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        let mi = 0.5 + rng.next_f64();
        if lumped {
            m.set(i, i, mi);
        } else {
            m.set(i, i, 2.0 * mi / 3.0);
            if i > 0 {
                m.set(i, i - 1, mi / 6.0);
            }
        }
        let ki = 1.0 + 3.0 * rng.next_f64();
        k.set(i, i, 2.0 * ki);
        if i > 0 {
            k.set(i, i - 1, -ki);
        }
    }
    let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
    let mut contacts = vec![Contact::new(0, Bounds { lo: -0.05 * rng.next_f64(), hi: 0.1 + 0.1 * rng.next_f64() }, false)];
    if two {
        contacts.push(Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: 0.02 * rng.next_f64() }, false));
    }
    let damping = damped.then(|| m.lin_comb(0.1, &k, 0.02));
    let shape: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.5).collect();
    let dy = Dynamics::new(m, k, load, contacts).with_damping(damping).with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 0.8, omega: 3.0 } }]);
    let u = vec![0.0, 0.01, -0.01, 0.0];
    let v: Vec<f64> = (0..n).map(|_| 2.0 * rng.next_f64() - 1.0).collect();
    (dy, Initial { u, v })
}

/// The step of Deuflhard–Krause–Ertel, dense: `(U, V, λ)` after one step.
struct Oracle {
    m: Dense,
    k: Dense,
    c: Option<Dense>,
    a: Dense,
    f: Vec<f64>,
    shape: Vec<f64>,
    cons: Vec<(usize, f64, f64)>,
    dt: f64,
}

impl Oracle {
    fn new(dy: &Dynamics, dt: f64) -> Self {
        let (m, k) = (dense(&dy.mass), dense(&dy.stiffness));
        let c = dy.damping.as_ref().map(dense);
        let n = m.len();
        let a = (0..n).map(|i| (0..n).map(|j| m[i][j] + dt * dt / 4.0 * k[i][j] + c.as_ref().map_or(0.0, |c| dt / 2.0 * c[i][j])).collect()).collect();
        let cons = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi)).collect();
        Self { m, k, c, a, f: dy.load.clone(), shape: dy.forcing.first().map_or(vec![0.0; n], |f| f.shape.clone()), cons, dt }
    }

    fn load(&self, t: f64) -> Vec<f64> {
        let s = 0.8 * (3.0 * t).sin();
        self.f.iter().zip(&self.shape).map(|(f, g)| f + s * g).collect()
    }

    /// One step from `(u, v)` at level `n`: `(U, V, λ, whether the
    /// stabilisation moved the predictor)`.
    fn step(&self, u: &[f64], v: &[f64], n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, bool) {
        let (u1, v1, lam, moved, _) = self.step_full(u, v, n);
        (u1, v1, lam, moved)
    }

    /// [`Self::step`], with the energy change the paper's identity gives
    /// (docs/theory.md §7.9): `ΔE = 2/τ² Σ_i [μ_i (u'_i − u_i) − ν_i (u'_i − p_i)]`
    /// at the contact dofs, `μ` the step's multipliers, `ν` the stabilisation's.
    fn step_full(&self, u: &[f64], v: &[f64], n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, bool, f64) {
        let (dt, nn) = (self.dt, u.len());
        let raw: Vec<f64> = u.iter().zip(v).map(|(u, v)| u + dt * v).collect();
        let (pred, nu) = box_qp(&self.m, &raw, &self.cons);
        let moved = pred.iter().zip(&raw).any(|(p, r)| p != r);
        let (mp, ku) = (mv(&self.m, &pred), mv(&self.k, u));
        let (f0, f1) = (self.load(n as f64 * dt), self.load((n + 1) as f64 * dt));
        let mut b: Vec<f64> = (0..nn).map(|i| mp[i] - dt * dt / 4.0 * ku[i] + dt * dt / 4.0 * (f0[i] + f1[i])).collect();
        if let Some(c) = &self.c {
            let cp = mv(c, &pred);
            let cv = mv(c, v);
            for i in 0..nn {
                b[i] += dt / 2.0 * cp[i] - dt * dt / 2.0 * cv[i];
            }
        }
        let y = solve(self.a.clone(), b);
        let (u1, mu) = box_qp(&self.a, &y, &self.cons);
        let v1: Vec<f64> = (0..nn).map(|i| v[i] + 2.0 / dt * (u1[i] - pred[i])).collect();
        let lam = mu.iter().map(|m| -2.0 * m / (dt * dt)).collect();
        let de = 2.0 / (dt * dt) * self.cons.iter().enumerate().map(|(i, &(c, _, _))| mu[i] * (u1[c] - u[c]) - nu[i] * (u1[c] - pred[c])).sum::<f64>();
        (u1, v1, lam, moved, de)
    }
}

/// Step by step against the dense transcription, 80 steps, on lumped and
/// consistent masses, with and without damping, one and two contacts.
#[test]
fn contact_stabilized_follows_the_papers_step_step_by_step() {
    let spec: SchemeSpec = "contact-stabilized".parse().unwrap();
    let mut rng = SplitMix64::new(20080704);
    let (mut active, mut stabilised, mut worst) = (0usize, 0usize, 0.0f64);
    for case in 0..16 {
        let (lumped, damped, two) = (case & 1 == 1, case & 2 == 2, case & 4 == 4);
        let (dy, init) = system(&mut rng, lumped, damped, two);
        let dt = 0.04 + 0.04 * rng.next_f64();
        let oracle = Oracle::new(&dy, dt);
        let mut s = spec.build(dy, dt, &init).unwrap();
        let (mut u, mut v) = (init.u.clone(), init.v.clone());
        for n in 0..80 {
            let (u1, v1, lam, moved) = oracle.step(&u, &v, n);
            s.step().unwrap();
            let st = s.state().unwrap();
            let scale = 1.0 + u1.iter().chain(&v1).fold(0.0f64, |m, x| m.max(x.abs()));
            for (i, (got, want)) in st.iter().zip(u1.iter().chain(&v1)).enumerate() {
                let e = (got - want).abs() / scale;
                worst = worst.max(e);
                assert!(e <= 1e-12, "case {case}, step {n}, state {i}: {got} vs {want}");
            }
            let lscale = 1.0 + lam.iter().fold(0.0f64, |m: f64, x: &f64| m.max(x.abs()));
            for (got, want) in s.contact_forces().iter().zip(&lam) {
                assert!((got - want).abs() <= 1e-10 * lscale, "case {case}, step {n}: λ {got} vs {want}");
            }
            active += lam.iter().filter(|l| **l != 0.0).count();
            stabilised += usize::from(moved);
            (u, v) = (u1, v1);
        }
    }
    // Not vacuous: contacts held and predictors moved in many steps.
    assert!(active > 100 && stabilised > 50, "active {active}, stabilised {stabilised}");
    eprintln!("contact-stabilized vs the dense step: worst {worst:.1e}, {active} active contact-steps, {stabilised} stabilised predictors");
}

/// Deuflhard–Krause–Ertel's claim: without damping and time-dependent
/// load the energy `½VᵀMV + ½UᵀKU − FᵀU` (computed here, dense) never
/// grows, through impacts, holds and releases at both contacts — and it
/// changes by exactly the identity of docs/theory.md §7.9, each of whose
/// two terms is ≤ 0 (from the oracle's multipliers).
#[test]
fn contact_stabilized_never_gains_energy_without_damping_or_forcing() {
    let spec: SchemeSpec = "contact-stabilized".parse().unwrap();
    let mut rng = SplitMix64::new(77);
    let (mut drops, mut worst) = (0, 0.0f64);
    for case in 0..8 {
        let (dy, init) = system(&mut rng, case & 1 == 1, false, true);
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), dy.load.clone(), dy.contacts.clone());
        let n = dy.n();
        let (m, k, f) = (dense(&dy.mass), dense(&dy.stiffness), dy.load.clone());
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let energy = |u: &[f64], v: &[f64]| 0.5 * dot(&mv(&m, v), v) + 0.5 * dot(&mv(&k, u), u) - dot(&f, u);
        let dt = 0.05;
        let oracle = Oracle::new(&dy, dt);
        let mut s = spec.build(dy, dt, &init).unwrap();
        let (mut u, mut v) = (init.u.clone(), init.v.clone());
        let mut e0 = energy(&u, &v);
        for step in 0..400 {
            let (_, _, _, _, de) = oracle.step_full(&u, &v, step);
            assert!(de <= 1e-12 * (1.0 + e0.abs()), "case {case}, step {step}: the identity's change {de} > 0");
            s.step().unwrap();
            let st = s.state().unwrap();
            (u, v) = (st[..n].to_vec(), st[n..].to_vec());
            let e1 = energy(&u, &v);
            assert!(e1 <= e0 + 1e-12 * (1.0 + e0.abs()), "case {case}, step {step}: energy {e0} -> {e1}");
            let err = ((e1 - e0) - de).abs() / (1.0 + e0.abs());
            worst = worst.max(err);
            assert!(err <= 1e-12, "case {case}, step {step}: ΔE {} vs the identity's {de}", e1 - e0);
            drops += usize::from(e1 < e0 - 1e-9 * (1.0 + e0.abs()));
            e0 = e1;
        }
    }
    assert!(drops > 20, "the contacts dissipated in only {drops} steps: the test would be vacuous");
    eprintln!("contact-stabilized energy identity: worst {worst:.1e}, {drops} dissipating steps");
}

/// With damping and a time-dependent load the energy balance
/// `Eⁿ − E⁰ = W_f + W_c − D` (docs/theory.md §7.9) holds at every level, the
/// energy computed here densely and the works reported by the scheme; the
/// contacts' work never grows (each step's share is ≤ 0).
#[test]
fn contact_stabilized_reports_its_work_and_the_balance_closes() {
    let spec: SchemeSpec = "contact-stabilized".parse().unwrap();
    let mut rng = SplitMix64::new(2012);
    let (mut worst, mut contact_drops) = (0.0f64, 0);
    for case in 0..8 {
        let (dy, init) = system(&mut rng, case & 1 == 1, case & 2 == 2, true);
        let n = dy.n();
        let (m, k, f) = (dense(&dy.mass), dense(&dy.stiffness), dy.load.clone());
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let energy = |u: &[f64], v: &[f64]| 0.5 * dot(&mv(&m, v), v) + 0.5 * dot(&mv(&k, u), u) - dot(&f, u);
        let mut s = spec.build(dy, 0.05, &init).unwrap();
        let e0 = energy(&init.u, &init.v);
        let mut wc_prev = 0.0;
        for step in 0..300 {
            s.step().unwrap();
            let st = s.state().unwrap();
            let e = energy(&st[..n], &st[n..]);
            let (wf, wc) = s.work().expect("contact-stabilized reports its work");
            let d = s.dissipation().expect("and its dissipation");
            let err = ((e - e0) - (wf + wc - d)).abs() / (1.0 + e0.abs());
            worst = worst.max(err);
            assert!(err <= 1e-11, "case {case}, step {step}: E − E⁰ = {} but W_f + W_c − D = {}", e - e0, wf + wc - d);
            assert!(wc <= wc_prev + 1e-12 * (1.0 + e0.abs()), "case {case}, step {step}: the contacts' work grew {wc_prev} -> {wc}");
            contact_drops += usize::from(wc < wc_prev - 1e-9);
            wc_prev = wc;
        }
    }
    assert!(contact_drops > 20, "the contacts worked in only {contact_drops} steps");
    eprintln!("contact-stabilized energy balance: worst {worst:.1e}, {contact_drops} dissipating contact steps");
}

/// The cases a user meets first. (a) Starting in contact, held: from the
/// static state with the contact node on its stop under a load pressing
/// it there (solved here, densely, with the node fixed), the scheme stays
/// at rest for 2 000 steps and reports the static reaction as its force.
/// (b) Symmetric contacts reached together: a mirror-symmetric chain with
/// opposite stops at both ends and antisymmetric data stays antisymmetric,
/// both contacts engaging at the same steps, and every step is the dense
/// step's.
#[test]
fn contact_stabilized_held_starts_and_symmetric_contacts() {
    let spec: SchemeSpec = "contact-stabilized".parse().unwrap();
    // (a) Held start: lumped and consistent masses.
    for lumped in [true, false] {
        let mut rng = SplitMix64::new(5);
        let (dy, _) = system(&mut rng, lumped, false, false);
        let n = dy.n();
        let lo = dy.contacts[0].bounds.lo;
        let mut load = vec![0.3, 0.1, -0.2, 0.05];
        load[0] = -2.0; // presses the node onto its lower stop
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), load.clone(), dy.contacts.clone());
        let k = dense(&dy.stiffness);
        let kf: Dense = (1..n).map(|i| (1..n).map(|j| k[i][j]).collect()).collect();
        let rf: Vec<f64> = (1..n).map(|i| load[i] - k[i][0] * lo).collect();
        let mut u_static = vec![lo];
        u_static.extend(solve(kf, rf));
        let reaction = mv(&k, &u_static)[0] - load[0];
        assert!(reaction > 0.0, "the load must press the node onto the stop");
        let mut s = spec.build(dy, 0.05, &Initial { u: u_static.clone(), v: vec![0.0; n] }).unwrap();
        for step in 0..2000 {
            s.step().unwrap();
            let st = s.state().unwrap();
            for i in 0..n {
                assert!((st[i] - u_static[i]).abs() <= 1e-12 && st[n + i].abs() <= 1e-10, "lumped {lumped}, step {step}: left the static state: {st:?}");
            }
            let lam = s.contact_forces()[0];
            assert!((lam + reaction).abs() <= 1e-10 * (1.0 + reaction), "lumped {lumped}, step {step}: λ {lam} vs the static reaction −{reaction}");
        }
    }
    // (b) A mirror-symmetric chain: uniform lumped mass, springs between
    // nodes and to the ground, stops at −g (node 0) and +g (node 3).
    let n = 4;
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, 1.0);
        k.set(i, i, if i == 0 || i == n - 1 { 1.5 } else { 2.5 });
        if i > 0 {
            k.set(i, i - 1, -1.0);
        }
    }
    let g = 0.05;
    let contacts = vec![Contact::new(0, Bounds { lo: -g, hi: f64::INFINITY }, false), Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: g }, false)];
    let dy = Dynamics::new(m, k, vec![0.0; n], contacts);
    let init = Initial { u: vec![0.0; n], v: vec![-1.0, -0.3, 0.3, 1.0] };
    let dt = 0.05;
    let oracle = Oracle::new(&dy, dt);
    let mut s = spec.build(dy, dt, &init).unwrap();
    let (mut u, mut v) = (init.u.clone(), init.v.clone());
    let mut together = 0;
    for step in 0..400 {
        let (u1, v1, lam, _) = oracle.step(&u, &v, step);
        s.step().unwrap();
        let st = s.state().unwrap();
        for (i, (a, b)) in st.iter().zip(u1.iter().chain(&v1)).enumerate() {
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "step {step}, state {i}: {a} vs the dense step's {b}");
        }
        assert!((st[0] + st[3]).abs() <= 1e-13 && (st[1] + st[2]).abs() <= 1e-13, "step {step}: symmetry lost {st:?}");
        let f = s.contact_forces();
        assert_eq!(f[0] != 0.0, f[1] != 0.0, "step {step}: one contact engaged without its mirror: {f:?}");
        assert!((f[0] + f[1]).abs() <= 1e-10 * (1.0 + f[0].abs()), "step {step}: mirror forces {f:?}");
        together += usize::from(lam[0] != 0.0);
        (u, v) = (u1, v1);
    }
    assert!(together > 10, "the two contacts engaged together in only {together} steps");
}

/// The fused tridiagonal step (the right-hand side `M U_pred − τ²/4 K Uⁿ +
/// …` and the forcing terms inside the solve's forward sweep, in chunks of
/// 32 rows) is the plain step bit for bit: against the same scheme with it
/// switched off (`SymBand::mul_vec`, `add_terms`, `BandLdlt::solve_in_place`),
/// `U`, `V`, the predictor, λ, the report and both works are equal
/// (`to_bits`) at every step — chains of 2, 3, 33 (one full chunk after
/// row 0), 40 and 100 dofs, lumped and consistent masses, one contact at
/// dof 0 or two (one two-sided, one in the middle), a steady load and two
/// sine terms, random states every 25 steps (contacts starting active and
/// inactive), the baseline build and the one the CPU selects.
#[test]
fn fused_tridiagonal_step_is_the_plain_step_bit_for_bit() {
    let mut rng = SplitMix64::new(35);
    let (mut held, mut free, mut fused_steps) = (0usize, 0usize, 0usize);
    for n in [2usize, 3, 33, 40, 100] {
        for case in 0..4 {
            let (lumped, two) = (case & 1 == 1, case & 2 == 2);
            let (m, k) = crate::fused_bar::chain(&mut rng, n, lumped, false);
            let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
            let mut contacts = vec![Contact::new(0, Bounds { lo: -0.02, hi: f64::INFINITY }, false)];
            if two && n > 2 {
                contacts.push(Contact::new(n / 2, Bounds { lo: -0.03, hi: 0.01 }, false));
            }
            let terms = (0..2).map(|j| Forcing { shape: (0..n).map(|_| rng.next_f64() - 0.5).collect(), time: TimeProfile::Sine { amplitude: 0.5 + j as f64, omega: 3.0 + 2.0 * j as f64 } }).collect();
            let dy = Dynamics::new(m, k, load, contacts).with_forcing(terms);
            let init = Initial { u: vec![0.0; n], v: (0..n).map(|_| rng.next_f64() - 0.5).collect() };
            for portable in [false, true] {
                let dt = 0.05;
                let build = || ContactStabilized::new("cs".into(), dy.clone(), dt, &init).unwrap();
                let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                plain.set_fused(false);
                assert!(!plain.fused() && fused.fused(), "n = {n}: the fused step applies");
                for step in 0..200 {
                    let what = format!("n = {n}, case {case}, portable {portable}, step {step}");
                    if step % 25 == 24 {
                        let st: Vec<f64> = (0..2 * n).map(|i| if i < n { 0.06 * (rng.next_f64() - 0.5) } else { rng.next_f64() - 0.5 }).collect();
                        plain.set_state(&st).unwrap();
                        fused.set_state(&st).unwrap();
                    }
                    let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
                    fused_steps += 1;
                    assert_eq!(ra, rb, "{what}: report");
                    let b = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert!(b(&plain.state().unwrap()) == b(&fused.state().unwrap()), "{what}: U, V");
                    assert!(b(plain.predictor()) == b(fused.predictor()), "{what}: predictor");
                    assert!(b(plain.contact_forces()) == b(fused.contact_forces()), "{what}: λ");
                    let (wa, wb) = (plain.work().unwrap(), fused.work().unwrap());
                    assert!(wa.0.to_bits() == wb.0.to_bits() && wa.1.to_bits() == wb.1.to_bits(), "{what}: work {wa:?} vs {wb:?}");
                    if plain.contact_forces().iter().any(|l| *l != 0.0) {
                        held += 1;
                    } else {
                        free += 1;
                    }
                }
            }
        }
    }
    assert!(held > 300 && free > 300 && fused_steps == 8000, "{held} steps with a contact force, {free} without");
}
