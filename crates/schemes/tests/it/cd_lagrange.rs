//! `cd-lagrange(e)` (docs/theory.md §4.6.9) against a dense transcription
//! of its equations written here: the central difference with half-step
//! velocities, `U^{n+1} = Uⁿ + dt V^{n+½}`, the contacts closed at
//! `U^{n+1}` (gap `<= 0`), and on them Newton's law on the velocity level,
//! `V^{n+3/2} = V^{n+½} + dt M⁻¹(F(t_{n+1}) − K U^{n+1}) + M⁻¹HᵀΛ`,
//! `0 <= Λ ⊥ H V^{n+3/2} + e H V^{n+½} >= 0`, a linear complementarity
//! problem with `W = H M⁻¹ Hᵀ` solved by brute force (every active set,
//! dense Gaussian elimination), independently of the crate's contact
//! solves; the start `V^{½} = V⁰ + dt/2 a⁰` with the same law against `V⁰`.
//! Random small systems with lumped and consistent masses, a time-dependent
//! load, gaps, a two-sided contact and a second one, step by step to
//! 1e-12; the discrete energy identity of §7.11; a held start under a
//! reversing load; mirror stops reached together; a long run; the limit.

use crate::common::bar_scene;
use crate::stabilized::{dense, mv, solve, system, Dense};
use signorini_fem::{BarMass, SymBand};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, SchemeError, SchemeSpec, SplitMix64, Stepper, TimeProfile};

/// `0 <= x ⊥ W x + q >= 0` by trying every active set.
fn lcp(w: &Dense, q: &[f64]) -> Vec<f64> {
    let k = q.len();
    let scale = 1.0 + q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for code in 0..1usize << k {
        let set: Vec<usize> = (0..k).filter(|i| code >> i & 1 == 1).collect();
        let mut x = vec![0.0; k];
        if !set.is_empty() {
            let ws: Dense = set.iter().map(|&i| set.iter().map(|&j| w[i][j]).collect()).collect();
            let xs = solve(ws, set.iter().map(|&i| -q[i]).collect());
            for (&i, v) in set.iter().zip(xs) {
                x[i] = v;
            }
        }
        let r: Vec<f64> = mv(w, &x).iter().zip(q).map(|(a, b)| a + b).collect();
        if x.iter().all(|v| *v >= -1e-13 * scale) && r.iter().all(|v| *v >= -1e-13 * scale) {
            return x;
        }
    }
    panic!("no active set solves the LCP");
}

/// The equations of §4.6.9, dense.
struct Oracle {
    m: Dense,
    minv: Dense,
    k: Dense,
    f: Vec<f64>,
    /// The forcing `shape · amplitude sin(omega t)` (zero shape: none).
    shape: Vec<f64>,
    amplitude: f64,
    omega: f64,
    /// (dof, lo, hi, e).
    cons: Vec<(usize, f64, f64, f64)>,
    dt: f64,
}

impl Oracle {
    fn new(dy: &Dynamics, e: f64, dt: f64) -> Self {
        let (m, k) = (dense(&dy.mass), dense(&dy.stiffness));
        let n = m.len();
        let cols: Vec<Vec<f64>> = (0..n).map(|j| solve(m.clone(), (0..n).map(|i| f64::from(u8::from(i == j))).collect())).collect();
        let minv = (0..n).map(|i| (0..n).map(|j| cols[j][i]).collect()).collect();
        let cons = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi, c.restitution.unwrap_or(e))).collect();
        let (shape, amplitude, omega) = match dy.forcing.first() {
            Some(Forcing { shape, time: TimeProfile::Sine { amplitude, omega } }) => (shape.clone(), *amplitude, *omega),
            Some(_) => panic!("the oracle reads sine forcings only"),
            None => (vec![0.0; n], 0.0, 0.0),
        };
        Self { m, minv, k, f: dy.load.clone(), shape, amplitude, omega, cons, dt }
    }

    fn load(&self, t: f64) -> Vec<f64> {
        let s = self.amplitude * (self.omega * t).sin();
        self.f.iter().zip(&self.shape).map(|(f, g)| f + s * g).collect()
    }

    /// `M⁻¹(F(t) − K u)`.
    fn acc(&self, t: f64, u: &[f64]) -> Vec<f64> {
        let ku = mv(&self.k, u);
        mv(&self.minv, &self.load(t).iter().zip(&ku).map(|(f, k)| f - k).collect::<Vec<f64>>())
    }

    /// The velocity after the kick `kick` at `(t, u)` from `v`, with the law
    /// on the contacts closed at `u`; and each contact's impulse along its dof.
    fn velocity(&self, t: f64, u: &[f64], v: &[f64], kick: f64) -> (Vec<f64>, Vec<f64>) {
        let a = self.acc(t, u);
        let mut w: Vec<f64> = v.iter().zip(&a).map(|(v, a)| v + kick * a).collect();
        // +1 closed at the lower stop, −1 at the upper, 0 open.
        let s: Vec<f64> = self
            .cons
            .iter()
            .map(|&(c, lo, hi, _)| {
                if u[c] <= lo {
                    1.0
                } else if u[c] >= hi {
                    -1.0
                } else {
                    0.0
                }
            })
            .collect();
        let set: Vec<usize> = (0..s.len()).filter(|&i| s[i] != 0.0).collect();
        let mut along = vec![0.0; s.len()];
        if set.is_empty() {
            return (w, along);
        }
        let dof = |i: usize| self.cons[i].0;
        let wm: Dense = set.iter().map(|&i| set.iter().map(|&j| s[i] * s[j] * self.minv[dof(i)][dof(j)]).collect()).collect();
        let q: Vec<f64> = set.iter().map(|&i| s[i] * (w[dof(i)] + self.cons[i].3 * v[dof(i)])).collect();
        let x = lcp(&wm, &q);
        let w0 = w.clone();
        for (&i, xi) in set.iter().zip(&x) {
            along[i] = s[i] * xi;
            for (r, o) in w.iter_mut().enumerate() {
                *o += self.minv[r][dof(i)] * along[i];
            }
        }
        // The law holds: the new velocity is past −e·old on each closed contact.
        for &i in &set {
            let (c, e) = (dof(i), self.cons[i].3);
            assert!(s[i] * (w[c] + e * v[c]) >= -1e-12 * (1.0 + w0[c].abs()), "the dense law failed");
        }
        (w, along)
    }

    /// `E^{k+½} = ½ Vᵀ M V + ½ U^{k+1}ᵀ K U^k − Fᵀ(U^{k+1} + U^k)/2`, `V = V^{k+½}`.
    fn energy(&self, u1: &[f64], u0: &[f64], v: &[f64]) -> f64 {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        0.5 * dot(&mv(&self.m, v), v) + 0.5 * dot(u1, &mv(&self.k, u0)) - 0.5 * dot(&self.f, &u1.iter().zip(u0).map(|(a, b)| a + b).collect::<Vec<f64>>())
    }
}

/// A run of the dense equations: `(U^k, V^{k−½})` after `k` steps and the
/// impulses `Λ^{k−1}` (at `t_{k−1}`) the `k`-th step reported.
struct DenseRun<'a> {
    o: &'a Oracle,
    k: usize,
    u: Vec<f64>,
    /// `V^{k+½}` (the velocity the next position update takes).
    vh: Vec<f64>,
}

impl<'a> DenseRun<'a> {
    /// The start: `V^{½}` from `(U⁰, V⁰)`; returns the run and `Λ⁰`.
    fn start(o: &'a Oracle, init: &Initial) -> (Self, Vec<f64>) {
        let (vh, big) = o.velocity(0.0, &init.u, &init.v, 0.5 * o.dt);
        (Self { o, k: 0, u: init.u.clone(), vh }, big)
    }

    /// `U^{k+1}` and `V^{k+1/2}` (the scheme's state after step `k + 1`),
    /// and the next velocity `V^{k+3/2}` with its impulse `Λ^{k+1}`.
    fn advance(&mut self) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let h = self.o.dt;
        let u1: Vec<f64> = self.u.iter().zip(&self.vh).map(|(u, v)| u + h * v).collect();
        let state_v = self.vh.clone();
        self.k += 1;
        let (vnext, big) = self.o.velocity(self.k as f64 * h, &u1, &self.vh, h);
        self.u = u1.clone();
        self.vh = vnext;
        (u1, state_v, big)
    }
}

fn build(dy: Dynamics, e: f64, dt: f64, init: &Initial) -> Box<dyn Stepper> {
    SchemeSpec::cd_lagrange(e).build(dy, dt, init).unwrap()
}

/// Step by step against the dense equations, 200 steps, on lumped and
/// consistent masses, with a time-dependent load, one and two contacts
/// (the first two-sided), the scheme's restitution and each contact's own:
/// positions, half-step velocities, and the reported force `−Λ/dt` at the
/// time the step names (`−Λ⁰/(dt/2)` for the start's half step).
#[test]
fn cd_lagrange_follows_the_dense_equations_step_by_step() {
    let mut rng = SplitMix64::new(2017);
    let (mut impulses, mut worst, mut both) = (0usize, 0.0f64, 0usize);
    for case in 0..24 {
        let (lumped, two) = (case & 1 == 1, case & 4 == 4);
        let (dy, init) = system(&mut rng, lumped, false, two);
        let mut dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), dy.load.iter().map(|f| 3.0 * f).collect(), dy.contacts.clone()).with_forcing(dy.forcing.clone());
        let e = [0.0, 0.5, 1.0][case % 3];
        if case >= 8 {
            dy.contacts[0].restitution = Some(rng.next_f64());
        }
        let limit = SchemeSpec::cd_lagrange(e).cfl_limit(&dy).unwrap().unwrap();
        let dt = limit * (0.3 + 0.6 * rng.next_f64());
        let oracle = Oracle::new(&dy, e, dt);
        let mut s = build(dy, e, dt, &init);
        let (mut run, mut big) = DenseRun::start(&oracle, &init);
        for n in 0..200 {
            let (u, v, next_big) = run.advance();
            let report = s.step().unwrap();
            let st = s.state().unwrap();
            let scale = 1.0 + u.iter().chain(&v).fold(0.0f64, |m, x| m.max(x.abs()));
            for (i, (got, want)) in st.iter().zip(u.iter().chain(&v)).enumerate() {
                let err = (got - want).abs() / scale;
                worst = worst.max(err);
                assert!(err <= 1e-12, "case {case}, step {n}, state {i}: {got} vs {want}");
            }
            for (i, got) in s.contact_forces().iter().enumerate() {
                // The start's impulse completes a half step.
                let want = -big[i] / if n == 0 { 0.5 * dt } else { dt };
                assert!((got - want).abs() <= 1e-10 * (1.0 + want.abs()), "case {case}, step {n}: λ_{i} {got} vs {want}");
            }
            let (tl, _) = report.lambda.unwrap();
            assert!((tl - n as f64 * dt).abs() <= 1e-12 * (1.0 + tl), "case {case}, step {n}: force reported at {tl}, not t_{n}");
            impulses += big.iter().filter(|x| **x != 0.0).count();
            both += usize::from(big.len() == 2 && big.iter().all(|x| *x != 0.0));
            big = next_big;
        }
    }
    // Not vacuous: many impulse steps, some with both contacts.
    assert!(impulses > 400 && both > 5, "impulses {impulses}, both contacts at once {both}");
    eprintln!("cd-lagrange vs the dense equations: worst {worst:.1e}; {impulses} impulses, {both} steps with both contacts");
}

/// The discrete energy identity of docs/theory.md §7.11: with
/// `E^{k+½} = ½ V^{k+½}ᵀ M V^{k+½} + ½ U^{k+1}ᵀ K U^k − Fᵀ(U^{k+1} + U^k)/2`
/// (computed here, dense, on the scheme's states),
/// `E^{k+½} − E^{k−½} = ½ (F(t_k) − F)ᵀ (U^{k+1} − U^{k−1}) + ½ Σ Λ_i (V^{k+½} + V^{k−½})_{c_i}`
/// (the impulses from the dense run): conserved off contact with a steady
/// load; with e = 1 conserved through the impacts too (each term is
/// `½ Λ_i (1 − e) V^{k−½}_{c_i}`); the scheme's own `energy()` is this `E`.
#[test]
fn cd_lagrange_keeps_its_discrete_energy_identity() {
    let mut rng = SplitMix64::new(2019);
    let (mut worst, mut contact_steps) = (0.0f64, 0usize);
    for case in 0..12 {
        let (dy, init) = system(&mut rng, case & 1 == 1, false, true);
        let forced = case & 2 == 2;
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), dy.load.iter().map(|f| 3.0 * f).collect(), dy.contacts.clone()).with_forcing(if forced { dy.forcing.clone() } else { vec![] });
        let n = dy.n();
        let e = [0.0, 0.3, 1.0][case % 3];
        let dt = 0.5 * SchemeSpec::cd_lagrange(e).cfl_limit(&dy).unwrap().unwrap();
        let oracle = Oracle::new(&dy, e, dt);
        let mut s = build(dy, e, dt, &init);
        let (mut run, _) = DenseRun::start(&oracle, &init);
        // Level 1: U¹, V^{½}; `big` is Λ¹.
        let (_, _, mut big) = run.advance();
        s.step().unwrap();
        let st = s.state().unwrap();
        let (mut u_prev, mut u, mut v) = (init.u.clone(), st[..n].to_vec(), st[n..].to_vec());
        let mut e_old = oracle.energy(&u, &u_prev, &v);
        for k in 1..600 {
            // Λ^k (the impulse in V^{k+½}); the dense run moves to level k + 1.
            let (_, _, next_big) = run.advance();
            let big_k = std::mem::replace(&mut big, next_big);
            s.step().unwrap();
            let st = s.state().unwrap();
            let (u1, v1) = (st[..n].to_vec(), st[n..].to_vec());
            let e_new = oracle.energy(&u1, &u, &v1);
            let fk = oracle.load(k as f64 * dt);
            let mut de: f64 = (0..n).map(|i| 0.5 * (fk[i] - oracle.f[i]) * (u1[i] - u_prev[i])).sum();
            for (i, &(c, ..)) in oracle.cons.iter().enumerate() {
                de += 0.5 * big_k[i] * (v1[c] + v[c]);
            }
            let scale = 1.0 + e_old.abs();
            let err = ((e_new - e_old) - de).abs() / scale;
            worst = worst.max(err);
            assert!(err <= 1e-12, "case {case}, step {k}: ΔE {} vs the identity's {de}", e_new - e_old);
            if e == 1.0 && !forced {
                assert!((e_new - e_old).abs() <= 1e-12 * scale, "case {case}, step {k}: e = 1 and a steady load, yet E moved {e_old} -> {e_new}");
            }
            let (te, es) = s.energy().unwrap();
            assert!((te - (k as f64 + 0.5) * dt).abs() <= 1e-12 && (es - e_new).abs() <= 1e-12 * scale, "case {case}, step {k}: energy() {es} at {te} vs E^{{k+½}} {e_new}");
            contact_steps += usize::from(big_k.iter().any(|x| *x != 0.0));
            (u_prev, u, v, e_old) = (u, u1, v1, e_new);
        }
    }
    assert!(contact_steps > 200, "only {contact_steps} impulse steps");
    eprintln!("cd-lagrange energy identity: worst {worst:.1e}, {contact_steps} impulse steps");
}

/// A held start under a reversing load. The chain starts at its static
/// state (solved here, densely, with node 0 fixed on its stop) under a
/// steady load pressing node 0 there; a load on node 0 alone,
/// `4 sin(t/20)`, unloads it, so the rest of the chain stays static while node
/// 0 is held. Node 0 is held (every dof at its static value, every
/// velocity zero) exactly as long as the force it needs,
/// `λ(t_k) = F₀(t_k) − (K U)₀`, is compressive; its reported force is that
/// value at `t_k`; at the first `t_k` where it is not, the node leaves.
#[test]
fn cd_lagrange_holds_a_start_until_the_load_reverses() {
    for lumped in [true, false] {
        let mut rng = SplitMix64::new(5);
        let (dy, _) = system(&mut rng, lumped, false, false);
        let n = dy.n();
        let lo = dy.contacts[0].bounds.lo;
        let mut load = vec![0.3, 0.1, -0.2, 0.05];
        load[0] = -2.0;
        let mut shape = vec![0.0; n];
        shape[0] = 1.0;
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), load.clone(), dy.contacts.clone()).with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 4.0, omega: 0.05 } }]);
        let k = dense(&dy.stiffness);
        let kf: Dense = (1..n).map(|i| (1..n).map(|j| k[i][j]).collect()).collect();
        let rf: Vec<f64> = (1..n).map(|i| load[i] - k[i][0] * lo).collect();
        let mut u_static = vec![lo];
        u_static.extend(solve(kf, rf));
        let ku0 = mv(&k, &u_static)[0];
        let force = |t: f64| load[0] + 4.0 * (0.05 * t).sin() - ku0;
        assert!(force(0.0) < 0.0, "the load must press node 0 onto its stop");
        let dt = 0.2 * SchemeSpec::cd_lagrange(0.5).cfl_limit(&dy).unwrap().unwrap();
        let mut s = build(dy, 0.5, dt, &Initial { u: u_static.clone(), v: vec![0.0; n] });
        let release = (0..).find(|&j| force(j as f64 * dt) > 0.0).unwrap();
        assert!(release > 20, "too early a release: step {release}");
        for step in 0..release {
            s.step().unwrap();
            let st = s.state().unwrap();
            for i in 0..n {
                assert!((st[i] - u_static[i]).abs() <= 1e-12 && st[n + i].abs() <= 1e-12, "lumped {lumped}, step {step}: left the static state while pressed: {st:?}");
            }
            let (lam, want) = (s.contact_forces()[0], force(step as f64 * dt));
            assert!((lam - want).abs() <= 1e-10 * (1.0 + want.abs()), "lumped {lumped}, step {step}: λ {lam} vs {want}");
        }
        // The step at t_release: no impulse, the node moves up.
        s.step().unwrap();
        assert_eq!(s.contact_forces()[0], 0.0, "lumped {lumped}: an impulse once the load pulls");
        let st = s.state().unwrap();
        assert!(st[n] > 0.0 && st[0] > lo, "lumped {lumped}: node 0 did not leave: {st:?}");
    }
}

/// Mirror stops reached together: a mirror-symmetric chain with opposite
/// stops at both ends and antisymmetric data stays antisymmetric, both
/// contacts engaging in the same steps, every step the dense equations'.
#[test]
fn cd_lagrange_reaches_mirror_stops_together() {
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
    for e in [0.0, 1.0] {
        let dt = 0.05;
        let oracle = Oracle::new(&dy, e, dt);
        let mut s = build(dy.clone(), e, dt, &init);
        let (mut run, _) = DenseRun::start(&oracle, &init);
        let mut together = 0;
        for step in 0..1000 {
            let (u, v, _) = run.advance();
            s.step().unwrap();
            let st = s.state().unwrap();
            for (i, (a, b)) in st.iter().zip(u.iter().chain(&v)).enumerate() {
                assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "e = {e}, step {step}, state {i}: {a} vs the dense step's {b}");
            }
            assert!((st[0] + st[3]).abs() <= 1e-13 && (st[1] + st[2]).abs() <= 1e-13, "e = {e}, step {step}: symmetry lost {st:?}");
            let f = s.contact_forces();
            assert_eq!(f[0] != 0.0, f[1] != 0.0, "e = {e}, step {step}: one contact engaged without its mirror: {f:?}");
            assert!((f[0] + f[1]).abs() <= 1e-10 * (1.0 + f[0].abs()), "e = {e}, step {step}: mirror forces {f:?}");
            together += usize::from(f[0] != 0.0);
        }
        assert!(together > 12, "e = {e}: the two contacts engaged together in only {together} steps");
    }
}

/// A long run: the lumped bar (m = 20) falling on its stop under gravity,
/// 2·10⁵ steps at 0.9 of the limit (some 300 bounces). With e = 1 its
/// energy `E^{k+½}` is conserved through every impact (§7.11: each impulse
/// term is `½ Λ (1 − e) V^{k−½}_c`) — measured to 1e-9 of the start's; with
/// e = 0 it stays bounded (at most 1.01× the start's) and the bar comes to
/// rest on the stop; no contact dof ever sits more than one step's travel
/// past its stop.
#[test]
fn cd_lagrange_long_run_on_the_bar() {
    let m = 20;
    let (dy, _) = bar_scene(m, BarMass::Lumped, true, -0.01, -0.5, None);
    let n = dy.n();
    let init = Initial { u: vec![0.0; n], v: vec![-1.0; n] };
    for e in [1.0, 0.0] {
        let spec = SchemeSpec::cd_lagrange(e);
        let dt = 0.9 * spec.cfl_limit(&dy).unwrap().unwrap();
        let mut s = spec.build(dy.clone(), dt, &init).unwrap();
        s.step().unwrap();
        let e0 = s.energy().unwrap().1;
        let (mut emax, mut emin, mut impacts, mut deepest) = (e0, e0, 0usize, 0.0f64);
        let mut vmax = 0.0f64;
        for _ in 0..200_000 {
            s.step().unwrap();
            let en = s.energy().unwrap().1;
            (emax, emin) = (emax.max(en), emin.min(en));
            impacts += usize::from(s.contact_forces()[0] != 0.0);
            let st = s.state().unwrap();
            vmax = vmax.max(st[n..].iter().fold(0.0f64, |a, x| a.max(x.abs())));
            deepest = deepest.max(-0.01 - st[0]);
        }
        eprintln!("cd-lagrange({e}) long run: E in [{emin}, {emax}] from {e0}, {impacts} impulse steps, deepest {deepest:e}, max |V| {vmax}");
        assert!(impacts > 300, "e = {e}: only {impacts} impulse steps");
        assert!(deepest <= dt * vmax.max(1.0), "e = {e}: a penetration {deepest} past one step's travel");
        if e == 1.0 {
            assert!((emax - e0).abs() <= 1e-9 * e0.abs() && (emin - e0).abs() <= 1e-9 * e0.abs(), "e = 1: E left {e0}: [{emin}, {emax}]");
        } else {
            assert!(emax <= e0 + 0.01 * e0.abs(), "e = 0: E grew from {e0} to {emax}");
        }
    }
}

/// The limit: on the lumped free bar the exact limit is the closed form
/// `2/sqrt(4c²/h²) = h/c`; a step equal to it is refused, a step 1e-6 below
/// taken. In free flight (the stop out of reach, rough data exciting every
/// mode) the bar stays bounded at 0.98× and grows at 1.02× (built past its
/// limit), lumped and std; pressed onto its stop it stays bounded at 0.98×.
#[test]
fn cd_lagrange_limit_is_the_central_difference_one() {
    let m = 8;
    let (dy, _) = bar_scene(m, BarMass::Lumped, true, -0.01, -0.5, None);
    let init = Initial { u: vec![0.0; m + 1], v: vec![-1.0; m + 1] };
    let h = 1.0 / m as f64;
    for e in [0.0, 1.0] {
        let spec = SchemeSpec::cd_lagrange(e);
        match spec.build(dy.clone(), h, &init) {
            Err(SchemeError::Unstable { limit, .. }) => assert!((limit - h).abs() <= 1e-12 * h, "limit {limit} against h/c = {h}"),
            Err(other) => panic!("e = {e}: dt = h/c refused for another reason: {other}"),
            Ok(_) => panic!("e = {e}: dt = h/c, the limit itself, accepted"),
        }
        assert!(spec.build(dy.clone(), h * (1.0 - 1e-6), &init).is_ok(), "e = {e}: a step just below the limit refused");
    }
    for mass in [BarMass::Lumped, BarMass::Std] {
        for (gap, body) in [(-1e3, 0.0), (0.0, -5.0)] {
            let (dy, _) = bar_scene(m, mass, false, gap, body, None);
            let n = dy.n();
            let init = Initial { u: (0..n).map(|i| -1e-3 * (1.0 + 0.3 * ((i * 7) % 5) as f64)).collect(), v: (0..n).map(|i| 0.01 * ((i * 3) % 4) as f64).collect() };
            let spec = SchemeSpec::cd_lagrange(0.0);
            let limit = spec.cfl_limit(&dy).unwrap().unwrap();
            let run = |dt: f64, spec: SchemeSpec| -> f64 {
                let mut s = spec.build(dy.clone(), dt, &init).unwrap();
                let mut worst = 0.0f64;
                for _ in 0..4000 {
                    match s.step() {
                        Ok(_) => worst = worst.max(s.displacement().iter().fold(0.0f64, |a, x| a.max(x.abs()))),
                        Err(_) => return f64::INFINITY,
                    }
                }
                worst
            };
            let below = run(0.98 * limit, spec);
            let above = run(1.02 * limit, spec.beyond_limit());
            eprintln!("cd-lagrange {mass:?}, stop at {gap}: max |U| {below} at 0.98×, {above} at 1.02×");
            assert!(below < 5.0, "{mass:?}, stop at {gap}: |U| = {below} below the limit");
            if gap < -1.0 {
                assert!(above > 1e3, "{mass:?} in free flight: |U| = {above} above the limit");
            }
        }
    }
}
