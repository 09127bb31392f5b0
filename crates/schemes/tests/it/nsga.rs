//! The nonsmooth generalized-α scheme `nsga(ρ∞,e)` (docs/theory.md §4.6.5):
//!
//! * its contact steps against a dense transcription of the papers'
//!   monolithic step written here (Chen, Acary, Virlez, Brüls 2013;
//!   Brüls, Acary, Cardona 2014): the smooth equation at the corrected
//!   positions, `M Y = Σ ν_i e_{c_i}`, `M W = Σ Λ_i e_{c_i}`, the position
//!   law at every contact and Newton's law on the index set, each small
//!   complementarity problem solved by enumerating its active sets — on
//!   random small systems with a steady load, a sine forcing, gaps, one to
//!   three contacts (lower, upper and two-sided stops, a restitution of
//!   their own), step by step to 1e-12;
//! * the paper's claims: the spectral radius of the linear step tends to
//!   ρ∞ as ω dt → ∞ (the characteristic polynomial of the amplification
//!   matrix against its closed-form limit `(λ + ρ∞)³`), second order off
//!   contact (a forced oscillator against its exact solution), and ρ∞ = 1
//!   conserving the energy off contact;
//! * the energy identity of docs/theory.md §7.6 at ρ∞ = 1 with impacts;
//! * the cases a user meets first against the same transcription, 2000
//!   steps each: a held start under a load that reverses, and
//!   mirror-symmetric stops reached together.

use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, SchemeSpec, SplitMix64, TimeProfile};

type Mat = Vec<Vec<f64>>;

fn dense(b: &SymBand) -> Mat {
    let n = b.n();
    (0..n).map(|i| (0..n).map(|j| b.get(i, j)).collect()).collect()
}

fn mv(a: &Mat, x: &[f64]) -> Vec<f64> {
    a.iter().map(|r| r.iter().zip(x).map(|(p, q)| p * q).sum()).collect()
}

/// Gaussian elimination with partial pivoting (`stabilized.rs`'s).
fn solve(a: &Mat, b: &[f64]) -> Vec<f64> {
    crate::stabilized::solve(a.clone(), b.to_vec())
}

/// The coefficients from ρ∞, written from Chung and Hulbert (1993).
fn coefficients(rho: f64) -> (f64, f64, f64, f64) {
    let am = (2.0 * rho - 1.0) / (rho + 1.0);
    let af = rho / (rho + 1.0);
    let g = 0.5 - am + af;
    (am, af, 0.25 * (g + 0.5) * (g + 0.5), g)
}

/// The box complementarity problem `x = x0 + D μ`, `lo_i <= x_i <= hi_i`,
/// `μ_i >= 0` at `lo`, `<= 0` at `hi`, `0` strictly inside, by enumerating
/// every assignment of the statuses (k <= 3): `(μ, status)`, status 0 free,
/// 1 lower, 2 upper.
fn box_lcp(x0: &[f64], d: &Mat, lo: &[f64], hi: &[f64]) -> (Vec<f64>, Vec<u8>) {
    let k = x0.len();
    let tol = 1e-13;
    'combo: for code in 0..3usize.pow(k as u32) {
        let st: Vec<u8> = (0..k).map(|i| ((code / 3usize.pow(i as u32)) % 3) as u8).collect();
        if (0..k).any(|i| (st[i] == 1 && lo[i] == f64::NEG_INFINITY) || (st[i] == 2 && hi[i] == f64::INFINITY)) {
            continue;
        }
        let act: Vec<usize> = (0..k).filter(|&i| st[i] != 0).collect();
        let mut mu = vec![0.0; k];
        if !act.is_empty() {
            let a: Mat = act.iter().map(|&i| act.iter().map(|&j| d[i][j]).collect()).collect();
            let b: Vec<f64> = act.iter().map(|&i| if st[i] == 1 { lo[i] } else { hi[i] } - x0[i]).collect();
            for (&i, m) in act.iter().zip(solve(&a, &b)) {
                mu[i] = m;
            }
        }
        for i in 0..k {
            let x = x0[i] + (0..k).map(|j| d[i][j] * mu[j]).sum::<f64>();
            let ok = match st[i] {
                0 => x >= lo[i] - tol * (1.0 + lo[i].abs()) && x <= hi[i] + tol * (1.0 + hi[i].abs()),
                1 => mu[i] >= -tol,
                _ => mu[i] <= tol,
            };
            if !ok {
                continue 'combo;
            }
        }
        return (mu, st);
    }
    panic!("no solution of the complementarity problem");
}

/// A random small system: tridiagonal (every fifth pentadiagonal) SPD `M`, a chain `K` tied at its far
/// end, a steady load, a sine forcing, `k` contacts (lower, upper or
/// two-sided stops), one with a restitution of its own.
struct Case {
    dy: Dynamics,
    init: Initial,
    rho: f64,
    e: f64,
    dt: f64,
}

fn case(seed: u64) -> Case {
    let mut r = SplitMix64::new(seed);
    let mut u = |a: f64, b: f64| a + (b - a) * r.next_f64();
    let n = 5 + (u(0.0, 3.0) as usize).min(2);
    // Every fifth system a pentadiagonal M (the general banded path; the
    // others take the fused tridiagonal sweeps).
    let wide = seed % 5 == 4;
    let p = if wide { 2 } else { 1 };
    let (mut m, mut k) = (SymBand::zeros(n, p), SymBand::zeros(n, p));
    for i in 0..n {
        m.set(i, i, u(1.0, 2.0));
        if i > 0 {
            m.set(i, i - 1, u(-0.3, 0.3));
        }
        if wide && i > 1 {
            m.set(i, i - 2, u(-0.2, 0.2));
        }
    }
    let springs: Vec<f64> = (0..=n).map(|_| u(0.5, 3.0)).collect();
    for i in 0..n {
        k.set(i, i, springs[i] * f64::from(u8::from(i > 0)) + springs[i + 1]);
        if i > 0 {
            k.set(i, i - 1, -springs[i]);
        }
    }
    let nc = 1 + (u(0.0, 3.0) as usize).min(2);
    let mut contacts = Vec::new();
    let dofs = [0, n / 2, n - 2];
    for (j, &dof) in dofs.iter().take(nc).enumerate() {
        let kind = (u(0.0, 3.0) as usize).min(2);
        let b = match kind {
            0 => Bounds::obstacle(u(-0.08, -0.01)),
            1 => Bounds { lo: f64::NEG_INFINITY, hi: u(0.01, 0.08) },
            _ => Bounds { lo: u(-0.08, -0.01), hi: u(0.01, 0.08) },
        };
        let own = (j == 1).then(|| u(0.0, 1.0));
        contacts.push(Contact::new(dof, b, false).with_restitution(own));
    }
    let load: Vec<f64> = (0..n).map(|_| u(-0.3, 0.3)).collect();
    let shape: Vec<f64> = (0..n).map(|_| u(-1.0, 1.0)).collect();
    let forcing = vec![Forcing { shape, time: TimeProfile::Sine { amplitude: u(0.5, 2.0), omega: u(1.0, 8.0) } }];
    let dy = Dynamics::new(m, k, load, contacts).with_forcing(forcing);
    let init = Initial { u: vec![0.0; n], v: (0..n).map(|_| u(-1.5, 1.5)).collect() };
    let rho = if seed % 4 == 0 {
        1.0
    } else if seed % 4 == 1 {
        0.0
    } else {
        u(0.0, 1.0)
    };
    let e = if seed % 3 == 0 { 0.0 } else { u(0.0, 1.0) };
    Case { dy, init, rho, e, dt: u(0.01, 0.08) }
}

/// The dense transcription of one step, from `(U, V, a, q̈)` at `t_n`.
struct Dense {
    m: Mat,
    k: Mat,
    load: Vec<f64>,
    shape: Vec<f64>,
    prof: TimeProfile,
    dofs: Vec<usize>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    e: Vec<f64>,
    rho: f64,
    dt: f64,
}

impl Dense {
    fn force(&self, t: f64) -> Vec<f64> {
        let s = self.prof.value(t);
        self.load.iter().zip(&self.shape).map(|(f, g)| f + s * g).collect()
    }

    /// `M⁻¹ E μ` (E the contact columns).
    fn minv_e(&self, mu: &[f64]) -> Vec<f64> {
        let mut b = vec![0.0; self.m.len()];
        for (&d, &x) in self.dofs.iter().zip(mu) {
            b[d] += x;
        }
        solve(&self.m, &b)
    }

    /// One step: the new `(U, V, a, q̈)` and the impulses `Λ`.
    #[allow(clippy::type_complexity)]
    fn step(&self, st: &(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>), t1: f64) -> ((Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>), Vec<f64>) {
        let (u, v, a, q) = st;
        let n = u.len();
        let kc = self.dofs.len();
        let h = self.dt;
        let (am, af, b, g) = coefficients(self.rho);
        let c = (1.0 - af) / (1.0 - am);
        let ah: Vec<f64> = (0..n).map(|i| (af * q[i] - am * a[i]) / (1.0 - am)).collect();
        let uh: Vec<f64> = (0..n).map(|i| u[i] + h * v[i] + h * h * ((0.5 - b) * a[i] + b * ah[i])).collect();
        let vh: Vec<f64> = (0..n).map(|i| v[i] + h * ((1.0 - g) * a[i] + g * ah[i])).collect();
        // The smooth equation at the corrected positions U = Û + c β h² q̈ + M⁻¹Eν:
        // (M + c β h² K) q̈ = F(t_{n+1}) − K (Û + M⁻¹Eν).
        let s: Mat = (0..n).map(|i| (0..n).map(|j| self.m[i][j] + c * b * h * h * self.k[i][j]).collect()).collect();
        let f1 = self.force(t1);
        let qdd_of = |nu: &[f64]| {
            let y = self.minv_e(nu);
            let x: Vec<f64> = (0..n).map(|i| uh[i] + y[i]).collect();
            let kx = mv(&self.k, &x);
            (solve(&s, &(0..n).map(|i| f1[i] - kx[i]).collect::<Vec<f64>>()), y)
        };
        let pos_of = |nu: &[f64]| {
            let (qq, y) = qdd_of(nu);
            (0..n).map(|i| uh[i] + c * b * h * h * qq[i] + y[i]).collect::<Vec<f64>>()
        };
        // Position law at every contact: u_c(ν) = u_c(0) + D ν, D column by column.
        let p0 = pos_of(&vec![0.0; kc]);
        let d: Mat = (0..kc)
            .map(|i| {
                (0..kc)
                    .map(|j| {
                        let mut ej = vec![0.0; kc];
                        ej[j] = 1.0;
                        pos_of(&ej)[self.dofs[i]] - p0[self.dofs[i]]
                    })
                    .collect()
            })
            .collect();
        let x0: Vec<f64> = self.dofs.iter().map(|&c| p0[c]).collect();
        let (nu, stat) = box_lcp(&x0, &d, &self.lo, &self.hi);
        let (q1, _) = qdd_of(&nu);
        let mut u1 = pos_of(&nu);
        for i in 0..kc {
            match stat[i] {
                1 => u1[self.dofs[i]] = self.lo[i],
                2 => u1[self.dofs[i]] = self.hi[i],
                _ => {}
            }
        }
        let a1: Vec<f64> = (0..n).map(|i| ah[i] + c * q1[i]).collect();
        let vp: Vec<f64> = (0..n).map(|i| vh[i] + g * h * c * q1[i]).collect();
        // Newton's law on the index set g(U^{n+1}) <= 0.
        let (mut vlo, mut vhi) = (vec![f64::NEG_INFINITY; kc], vec![f64::INFINITY; kc]);
        for i in 0..kc {
            let (uc, target) = (u1[self.dofs[i]], -self.e[i] * v[self.dofs[i]]);
            if uc <= self.lo[i] {
                vlo[i] = target;
            } else if uc >= self.hi[i] {
                vhi[i] = target;
            }
        }
        let dv: Mat = (0..kc)
            .map(|i| {
                (0..kc)
                    .map(|j| {
                        let mut ej = vec![0.0; kc];
                        ej[j] = 1.0;
                        self.minv_e(&ej)[self.dofs[i]]
                    })
                    .collect()
            })
            .collect();
        let y0: Vec<f64> = self.dofs.iter().map(|&c| vp[c]).collect();
        let (big, vst) = box_lcp(&y0, &dv, &vlo, &vhi);
        let w = self.minv_e(&big);
        let mut v1: Vec<f64> = (0..n).map(|i| vp[i] + w[i]).collect();
        for i in 0..kc {
            match vst[i] {
                1 => v1[self.dofs[i]] = vlo[i],
                2 => v1[self.dofs[i]] = vhi[i],
                _ => {}
            }
        }
        ((u1, v1, a1, q1), big)
    }
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, b| a.max(b.abs()))
}

/// Runs `cs` for `steps` steps with the scheme and with the dense
/// transcription side by side, asserting every step equal to 1e-12;
/// returns the worst relative difference, the steps with an impulse and
/// every step's `(U, V)` of the scheme.
fn follow(label: &str, cs: &Case, steps: usize) -> (f64, usize, Vec<Vec<f64>>) {
    let spec = SchemeSpec::nsga(cs.rho, cs.e);
    let mut s = spec.build(cs.dy.clone(), cs.dt, &cs.init).unwrap();
    let ([load, shape], prof) = ([cs.dy.load.clone(), cs.dy.forcing[0].shape.clone()], cs.dy.forcing[0].time.clone());
    let dn = Dense {
        m: dense(&cs.dy.mass),
        k: dense(&cs.dy.stiffness),
        load,
        shape,
        prof,
        dofs: cs.dy.contacts.iter().map(|c| c.dof).collect(),
        lo: cs.dy.contacts.iter().map(|c| c.bounds.lo).collect(),
        hi: cs.dy.contacts.iter().map(|c| c.bounds.hi).collect(),
        e: cs.dy.contacts.iter().map(|c| c.restitution.unwrap_or(cs.e)).collect(),
        rho: cs.rho,
        dt: cs.dt,
    };
    let f0 = dn.force(0.0);
    let ku = mv(&dn.k, &cs.init.u);
    let q0 = solve(&dn.m, &(0..f0.len()).map(|i| f0[i] - ku[i]).collect::<Vec<f64>>());
    let mut st = (cs.init.u.clone(), cs.init.v.clone(), q0.clone(), q0);
    let n = st.0.len();
    let (mut worst, mut hit, mut states) = (0.0f64, 0, Vec::with_capacity(steps));
    for step in 1..=steps {
        let (next, big) = dn.step(&st, step as f64 * cs.dt);
        st = next;
        s.step().unwrap();
        let got = s.state().unwrap();
        for (what, want, have) in [("U", &st.0, &got[..n]), ("V", &st.1, &got[n..2 * n]), ("a", &st.2, &got[2 * n..])] {
            let scale = max_abs(want).max(1.0);
            for (x, y) in want.iter().zip(have) {
                let r = (x - y).abs() / scale;
                worst = worst.max(r);
                assert!(r <= 1e-12, "{label} ({spec}, {} contacts) step {step}: {what} {have:?} against {want:?}", dn.dofs.len());
            }
        }
        let scale = max_abs(&big).max(1e-3);
        for (l, b) in s.contact_forces().iter().zip(&big) {
            assert!((-l * cs.dt - b).abs() <= 1e-12 * scale, "{label} step {step}: impulse {} against {b}", -l * cs.dt);
        }
        hit += usize::from(big.iter().any(|&b| b != 0.0));
        states.push(got[..2 * n].to_vec());
    }
    (worst, hit, states)
}

/// The scheme against the dense transcription, 300 steps on each of 24
/// random systems; at least 20 of them hit a stop.
#[test]
fn contact_steps_follow_the_dense_transcription() {
    let mut worst = 0.0f64;
    let (mut impacts, mut struck) = (0, 0);
    for seed in 0..24u64 {
        let (w, hit, _) = follow(&format!("seed {seed}"), &case(seed), 300);
        worst = worst.max(w);
        impacts += hit;
        struck += usize::from(hit > 0);
    }
    assert!(struck >= 20, "{struck} of 24 systems hit a stop");
    eprintln!("nsga vs its dense transcription: 24 systems x 300 steps ({struck} hit a stop), {impacts} steps with an impulse, worst relative difference {worst:.1e}");
}

/// A chain of `n` dofs, mirror-symmetric (`M`, `K` equal under
/// `i ↦ n − 1 − i`): tridiagonal `M` (2/3 on the diagonal, 1/6 beside it),
/// unit springs, both ends tied.
fn symmetric_chain(n: usize) -> (SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, 2.0 / 3.0);
        k.set(i, i, 2.0);
        if i > 0 {
            m.set(i, i - 1, 1.0 / 6.0);
            k.set(i, i - 1, -1.0);
        }
    }
    (m, k)
}

/// The cases a user meets first, against the same dense transcription,
/// 2000 steps each (long runs):
/// * a held start: the chain at rest on its stop (`U = 0`, `lo = 0`)
///   pressed by a load on the contact dof, `−1 + 2 sin t`, which reverses
///   at t = π/6 — held, released, struck again; while the load presses
///   (t < π/6) the contact dof stays on the stop and every dof at rest;
/// * mirror-symmetric contacts reached together: the symmetric chain with
///   a lower stop at dof 0 and an upper one at dof n − 1, each 0.05 away,
///   an antisymmetric start (v_i = −v_{n−1−i}) — both contacts strike at
///   the same step, and the motion stays antisymmetric to round-off.
#[test]
fn held_starts_and_symmetric_contacts_follow_the_dense_transcription() {
    let n = 6;
    for rho in [0.0, 0.5, 1.0] {
        // Held, under a load that reverses.
        let (m, k) = symmetric_chain(n);
        let mut load = vec![0.0; n];
        load[0] = -1.0;
        let mut shape = vec![0.0; n];
        shape[0] = 1.0;
        let forcing = vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 2.0, omega: 1.0 } }];
        let dy = Dynamics::new(m, k, load, vec![Contact::new(0, Bounds::obstacle(0.0), false)]).with_forcing(forcing);
        let cs = Case { dy, init: Initial { u: vec![0.0; n], v: vec![0.0; n] }, rho, e: 0.0, dt: 0.01 };
        let (w, hit, states) = follow(&format!("held start, ρ∞ = {rho}"), &cs, 2000);
        let pressing = (std::f64::consts::FRAC_PI_6 / 0.01) as usize - 1;
        for (j, x) in states.iter().take(pressing).enumerate() {
            assert!(max_abs(x) <= 1e-12, "held start, ρ∞ = {rho}: moved at step {} while the load presses: {x:?}", j + 1);
        }
        assert!(hit >= pressing, "held start, ρ∞ = {rho}: {hit} steps with an impulse");
        assert!(states.iter().skip(pressing).any(|x| x[0] > 1e-3), "held start, ρ∞ = {rho}: never released");
        eprintln!("nsga held start, ρ∞ = {rho}: 2000 steps, {hit} with an impulse, worst {w:.1e}");
        // Two stops reached together.
        for e in [0.0, 0.5] {
            let (m, k) = symmetric_chain(n);
            let contacts = vec![Contact::new(0, Bounds { lo: -0.05, hi: f64::INFINITY }, false), Contact::new(n - 1, Bounds { lo: f64::NEG_INFINITY, hi: 0.05 }, false)];
            let forcing = vec![Forcing { shape: vec![0.0; n], time: TimeProfile::Sine { amplitude: 0.0, omega: 1.0 } }];
            let dy = Dynamics::new(m, k, vec![0.0; n], contacts).with_forcing(forcing);
            let v: Vec<f64> = (0..n).map(|i| -0.5 * (1.0 - 2.0 * i as f64 / (n - 1) as f64)).collect();
            let cs = Case { dy, init: Initial { u: vec![0.0; n], v }, rho, e, dt: 0.01 };
            let (w, hit, states) = follow(&format!("symmetric stops, ρ∞ = {rho}, e = {e}"), &cs, 2000);
            assert!(hit > 0, "symmetric stops, ρ∞ = {rho}, e = {e}: no impact");
            for (j, x) in states.iter().enumerate() {
                for i in 0..n {
                    for (a, b) in [(x[i], x[n - 1 - i]), (x[n + i], x[2 * n - 1 - i])] {
                        assert!((a + b).abs() <= 1e-13, "symmetric stops, ρ∞ = {rho}, e = {e}: step {}: not antisymmetric at dof {i}: {a} against {b}", j + 1);
                    }
                }
            }
            eprintln!("nsga symmetric stops, ρ∞ = {rho}, e = {e}: 2000 steps, {hit} with an impulse, worst {w:.1e}");
        }
    }
}

/// One dof, `M = 1`, `K = ω²`, the stop far away: the amplification
/// matrix of the state `(U, V, a)` column by column (`set_state`).
fn amplification(rho: f64, omega_dt: f64) -> [[f64; 3]; 3] {
    let dt = 1.0;
    let (m, k) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[omega_dt * omega_dt]));
    let dy = Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1e300), false)]);
    let mut s = SchemeSpec::nsga(rho, 0.0).build(dy, dt, &Initial { u: vec![0.0], v: vec![0.0] }).unwrap();
    let mut a = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        s.set_state(&e).unwrap();
        s.step().unwrap();
        let x = s.state().unwrap();
        for i in 0..3 {
            a[i][j] = x[i];
        }
    }
    a
}

/// The invariants of a 3×3 matrix: trace, sum of principal 2×2 minors, determinant.
fn invariants(a: &[[f64; 3]; 3]) -> [f64; 3] {
    let tr = a[0][0] + a[1][1] + a[2][2];
    let m2 = a[0][0] * a[1][1] - a[0][1] * a[1][0] + a[0][0] * a[2][2] - a[0][2] * a[2][0] + a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    [tr, m2, det]
}

/// Chung and Hulbert's design: as ω dt → ∞ the three roots of the
/// amplification matrix tend to `−ρ∞`, its characteristic polynomial to
/// `(λ + ρ∞)³`: trace `−3ρ∞`, minors `3ρ∞²`, determinant `−ρ∞³`; and
/// the spectral radius (the largest root of the cubic, found here by
/// bisection on the modulus of its roots) tends to ρ∞.
#[test]
fn spectral_radius_at_infinity_is_rho_inf() {
    for rho in [0.0, 0.2, 0.5, 0.8, 0.95, 1.0] {
        let [tr, m2, det] = invariants(&amplification(rho, 1e4));
        eprintln!("ρ∞ = {rho}: invariants at ω dt = 1e4 {:?}", [tr, m2, det]);
        let want = [-3.0 * rho, 3.0 * rho * rho, -rho * rho * rho];
        for (g, w) in [tr, m2, det].iter().zip(want) {
            assert!((g - w).abs() <= 1e-6, "ρ∞ = {rho}: invariants {:?} against {want:?}", [tr, m2, det]);
        }
        // The spectral radius at ω dt = 1e4 from the cubic's roots (a near
        // triple root: its roots move by the cube root of the invariants' error).
        let r = spectral_radius(&amplification(rho, 1e4));
        assert!((r - rho).abs() <= 5e-3, "ρ∞ = {rho}: spectral radius {r}");
    }
    // And at moderate ω dt the scheme is dissipative (ρ∞ < 1) or on the unit
    // circle (ρ∞ = 1, the trapezoidal rule, its spurious root −1).
    let r = spectral_radius(&amplification(1.0, 2.0));
    assert!((r - 1.0).abs() <= 1e-9, "ρ∞ = 1 at ω dt = 2: spectral radius {r}");
    for rho in [0.0, 0.5, 0.9] {
        assert!(spectral_radius(&amplification(rho, 3.0)) < 1.0, "ρ∞ = {rho} at ω dt = 3");
    }
}

/// `ρ(A)` from the roots of the characteristic cubic `λ³ − tr λ² + m2 λ − det`
/// (all three found by Durand–Kerner iteration).
fn spectral_radius(a: &[[f64; 3]; 3]) -> f64 {
    let [tr, m2, det] = invariants(a);
    let p = |z: (f64, f64)| {
        let mul = |x: (f64, f64), y: (f64, f64)| (x.0 * y.0 - x.1 * y.1, x.0 * y.1 + x.1 * y.0);
        let z2 = mul(z, z);
        let z3 = mul(z2, z);
        (z3.0 - tr * z2.0 + m2 * z.0 - det, z3.1 - tr * z2.1 + m2 * z.1)
    };
    let mut roots = [(0.4, 0.9), (-0.65, 0.72), (0.1, -0.8)];
    for _ in 0..2000 {
        for i in 0..3 {
            let mut den = (1.0, 0.0);
            for j in 0..3 {
                if i != j {
                    let d = (roots[i].0 - roots[j].0, roots[i].1 - roots[j].1);
                    den = (den.0 * d.0 - den.1 * d.1, den.0 * d.1 + den.1 * d.0);
                }
            }
            let num = p(roots[i]);
            let q = den.0 * den.0 + den.1 * den.1;
            if q == 0.0 {
                continue;
            }
            let ratio = ((num.0 * den.0 + num.1 * den.1) / q, (num.1 * den.0 - num.0 * den.1) / q);
            roots[i] = (roots[i].0 - ratio.0, roots[i].1 - ratio.1);
        }
    }
    roots.iter().map(|r| r.0.hypot(r.1)).fold(0.0, f64::max)
}

/// Second order off contact: `q'' + ω² q = f sin(Ω t)` against its exact
/// solution at t = 2, dt = 0.02, 0.01, 0.005: the error ratios are 4 (order
/// 2 within 0.1) for every ρ∞.
#[test]
fn second_order_off_contact() {
    let (w, f, om, q0, v0) = (3.0f64, 2.0, 5.0, 0.3, -0.7);
    let exact = |t: f64| {
        let b = (v0 - f * om / (w * w - om * om)) / w;
        q0 * (w * t).cos() + b * (w * t).sin() + f / (w * w - om * om) * (om * t).sin()
    };
    for rho in [0.0, 0.3, 0.7, 1.0] {
        let errs: Vec<f64> = [0.02, 0.01, 0.005]
            .iter()
            .map(|&dt| {
                let (m, k) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[w * w]));
                let dy = Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1e3), false)])
                    .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: f, omega: om } }]);
                let mut s = SchemeSpec::nsga(rho, 0.0).build(dy, dt, &Initial { u: vec![q0], v: vec![v0] }).unwrap();
                let steps = (2.0 / dt).round() as usize;
                for _ in 0..steps {
                    s.step().unwrap();
                }
                (s.displacement()[0] - exact(2.0)).abs()
            })
            .collect();
        for p in errs.windows(2) {
            let order = (p[0] / p[1]).log2();
            assert!((order - 2.0).abs() <= 0.1, "ρ∞ = {rho}: errors {errs:?}, order {order}");
        }
    }
}

/// The 4-dof chain of the conformance suite with a steady load, the stop
/// far away: ρ∞ = 1 keeps `½VᵀMV + ½UᵀKU − FᵀU` to round-off over 2000
/// steps (the trapezoidal rule); ρ∞ = 0.5 loses energy in the stiff
/// modes at a large step.
#[test]
fn rho_one_conserves_the_energy_off_contact() {
    let n = 4;
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, if i == 0 { 1.0 / 3.0 } else { 2.0 / 3.0 });
        k.set(i, i, if i == 0 { 1.0 } else { 2.0 });
        if i > 0 {
            m.set(i, i - 1, 1.0 / 6.0);
            k.set(i, i - 1, -1.0);
        }
    }
    let dy = Dynamics::new(m, k, vec![0.01; n], vec![Contact::new(0, Bounds::obstacle(-1e3), false)]);
    let init = Initial { u: vec![0.02, -0.01, 0.015, 0.0], v: vec![-0.3, 0.2, -0.1, 0.05] };
    let e0 = dy.energy(&init.u, &init.v);
    let mut s = SchemeSpec::nsga(1.0, 0.0).build(dy.clone(), 0.3, &init).unwrap();
    for _ in 0..2000 {
        s.step().unwrap();
        let (_, e) = s.energy().unwrap();
        assert!((e - e0).abs() <= 1e-13, "ρ∞ = 1: energy {e} against {e0}");
    }
    let dy_k = dy.stiffness.clone();
    let mut s = SchemeSpec::nsga(0.5, 0.0).build(dy, 3.0, &init).unwrap();
    for _ in 0..200 {
        s.step().unwrap();
    }
    let (_, e) = s.energy().unwrap();
    // Relative to the static equilibrium's energy −½ Fᵀ K⁻¹ F.
    let kd: Mat = dense(&dy_k);
    let us = solve(&kd, &[0.01; 4]);
    let e_min = -0.5 * us.iter().map(|x| 0.01 * x).sum::<f64>();
    eprintln!("ρ∞ = 0.5, dt = 3, 200 steps: E − E_min = {:.3e} of {:.3e}", e - e_min, e0 - e_min);
    assert!(e - e_min < 0.5 * (e0 - e_min), "ρ∞ = 0.5 at a large step: energy {e}, start {e0}, minimum {e_min}");
}

/// The energy identity of docs/theory.md §7.6 at ρ∞ = 1, with impacts:
/// `ΔE = Σ_i [Λ_i (v̄_{c_i} + (dt/2) q̄̈_{c_i}) − ν_i q̄̈_{c_i}]` (bars: means
/// of the two levels), everything rebuilt here from the recorded states
/// `(U, V, a)`: `q̈ = M⁻¹(F − K U)` at each level, the position correction
/// `Y = ΔU − dt Vⁿ − dt²((½−β) aⁿ + β aⁿ⁺¹)` and the velocity jump
/// `W = ΔV − dt((1−γ) aⁿ + γ aⁿ⁺¹)`, whose `M Y`, `M W` must vanish off
/// the contact dofs (`ν_i`, `Λ_i` their entries there). Steady load,
/// random systems of [`case`], 300 steps each, to 1e-10 of the energy scale.
#[test]
fn rho_one_energy_identity_with_impacts() {
    let (mut worst, mut total) = (0.0f64, 0);
    for seed in 0..12u64 {
        let mut cs = case(seed);
        cs.dy.forcing.clear();
        let mut s = SchemeSpec::nsga(1.0, cs.e).build(cs.dy.clone(), cs.dt, &cs.init).unwrap();
        let (m, k, f) = (dense(&cs.dy.mass), dense(&cs.dy.stiffness), cs.dy.load.clone());
        let n = f.len();
        let (b, g, h) = (0.25, 0.5, cs.dt);
        let qdd = |u: &[f64]| {
            let ku = mv(&k, u);
            solve(&m, &(0..n).map(|i| f[i] - ku[i]).collect::<Vec<f64>>())
        };
        let energy = |u: &[f64], v: &[f64]| {
            let (mvv, kuu) = (mv(&m, v), mv(&k, u));
            (0..n).map(|i| 0.5 * v[i] * mvv[i] + 0.5 * u[i] * kuu[i] - f[i] * u[i]).sum::<f64>()
        };
        let mut x0: Vec<f64> = cs.init.u.iter().chain(&cs.init.v).copied().collect();
        x0.extend(qdd(&cs.init.u));
        let mut impacts = 0;
        for _ in 0..300 {
            s.step().unwrap();
            let x1 = s.state().unwrap();
            let (u0, v0, a0) = (&x0[..n], &x0[n..2 * n], &x0[2 * n..]);
            let (u1, v1, a1) = (&x1[..n], &x1[n..2 * n], &x1[2 * n..]);
            let y: Vec<f64> = (0..n).map(|i| u1[i] - u0[i] - h * v0[i] - h * h * ((0.5 - b) * a0[i] + b * a1[i])).collect();
            let w: Vec<f64> = (0..n).map(|i| v1[i] - v0[i] - h * ((1.0 - g) * a0[i] + g * a1[i])).collect();
            let (my, mw) = (mv(&m, &y), mv(&m, &w));
            let (q0, q1) = (qdd(u0), qdd(u1));
            let de = energy(u1, v1) - energy(u0, v0);
            let scale = energy(u0, v0).abs().max(1e-3);
            let mut rhs = 0.0;
            for i in 0..n {
                let on = cs.dy.contacts.iter().any(|c| c.dof == i);
                if !on {
                    assert!(my[i].abs() <= 1e-10 * scale && mw[i].abs() <= 1e-10 * scale, "seed {seed}: M Y, M W off the contacts {} {}", my[i], mw[i]);
                    continue;
                }
                let (vbar, qbar) = (0.5 * (v0[i] + v1[i]), 0.5 * (q0[i] + q1[i]));
                rhs += mw[i] * (vbar + 0.5 * h * qbar) - my[i] * qbar;
            }
            impacts += usize::from(mw.iter().any(|x| x.abs() > 1e-12));
            let r = (de - rhs).abs() / scale;
            worst = worst.max(r);
            assert!(r <= 1e-10, "seed {seed}: ΔE {de} against {rhs}");
            x0 = x1;
        }
        total += impacts;
    }
    assert!(total > 300, "{total} steps with an impulse");
    eprintln!("nsga ρ∞ = 1 energy identity: 12 systems x 300 steps, {total} with an impulse, worst {worst:.1e} of the energy scale");
}

/// The fused free step (the predictor, `F − K Û` and the forcing terms
/// inside `S`'s forward sweep, the updates inside its backward sweep, in
/// chunks of 32 rows) is the plain step bit for bit: against the same
/// scheme with it switched off (`Predictor` entry by entry,
/// `SymBand::mul_vec`, `add_terms`, `BandLdlt::solve_in_place`), `U`, `V`,
/// `a`, λ and the report are equal (`to_bits`) at every step — chains of
/// 2, 3, 33 (one full chunk after row 0), 34, 40 and 100 dofs, lumped and
/// consistent masses, one contact at dof 0 (the closed-form projections)
/// or two (one two-sided, one in the middle: the exact solves), a steady
/// load and two sine terms, ρ∞ = 0.8 and 0.3, random states every 25
/// steps, the baseline build and the one the CPU selects.
#[test]
fn fused_tridiagonal_step_is_the_plain_step_bit_for_bit() {
    use signorini_schemes::{Nsga, Stepper};
    let mut rng = SplitMix64::new(39);
    let (mut held, mut free, mut fused_steps) = (0usize, 0usize, 0usize);
    for n in [2usize, 3, 33, 34, 40, 100] {
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
            let (rho, e) = if case < 2 { (0.8, 0.0) } else { (0.3, 0.5) };
            for portable in [false, true] {
                let dt = 0.05;
                let build = || Nsga::new("nsga".into(), dy.clone(), rho, e, dt, &init).unwrap();
                let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                plain.set_fused(false);
                assert!(!plain.fused() && fused.fused(), "n = {n}: the fused step applies");
                for step in 0..200 {
                    let what = format!("n = {n}, case {case}, portable {portable}, step {step}");
                    if step % 25 == 24 {
                        let st: Vec<f64> = (0..3 * n).map(|i| if i < n { 0.06 * (rng.next_f64() - 0.5) } else { rng.next_f64() - 0.5 }).collect();
                        plain.set_state(&st).unwrap();
                        fused.set_state(&st).unwrap();
                    }
                    let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
                    fused_steps += 1;
                    assert_eq!(ra, rb, "{what}: report");
                    let b = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert!(b(&plain.state().unwrap()) == b(&fused.state().unwrap()), "{what}: U, V, a");
                    assert!(b(plain.contact_forces()) == b(fused.contact_forces()), "{what}: λ");
                    if plain.contact_forces().iter().any(|l| *l != 0.0) {
                        held += 1;
                    } else {
                        free += 1;
                    }
                }
            }
        }
    }
    assert!(held > 300 && free > 300 && fused_steps == 9600, "{held} steps with a contact force, {free} without");
}
