//! `d1-minus-linear(e)` (Schindler and Acary 2014, in Siconos's
//! half-explicit acceleration-level form; docs/theory.md §4.6.7) against a
//! dense transcription of the step written here from the equations of
//! §4.6.7: the index sets from the gaps and rates with Siconos's threshold
//! 1e-8, the two force problems on the acceleration level and the impact
//! problem on the velocity level, each a linear complementarity problem
//! `0 <= x ⊥ W x + q >= 0` with `W = H M⁻¹ Hᵀ`, solved by brute force
//! (every active set tried, dense Gaussian elimination), independently of
//! the crate's contact solves. Random small systems with lumped and
//! consistent masses, damping, a time-dependent load, gaps, a two-sided
//! contact and a second contact, step by step to 1e-12; the discrete energy
//! identity of §7.10; a held start and symmetric contacts.
//!
//! The same for `d1-minus-linear-velocity(e)`, the velocity level (§4.6.7):
//! its step transcribed here as Siconos's `computeResiduHalfExplicitVelocityLevel`
//! writes it (the residual `−h/2 a⁺ − ½M⁻¹Hᵀμ⁺ − h/2 a⁻`), its energy
//! identity (§7.10), and a long run.

use crate::stabilized::{dense, mv, solve, system, Dense};
use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, D1Level, D1MinusLinear, Dynamics, Initial, SchemeSpec, SplitMix64, Stepper, TimeProfile};

/// Siconos's `DEFAULT_TOL_D1MINUS`: the index sets' threshold.
const TOL: f64 = 1e-8;

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

/// A contact's closed side at `x`: +1 at its lower stop, −1 at its upper, 0 open.
fn side(lo: f64, hi: f64, x: f64) -> f64 {
    if x - lo <= TOL {
        1.0
    } else if hi - x <= TOL {
        -1.0
    } else {
        0.0
    }
}

/// One step's results.
pub(crate) struct Step {
    pub(crate) u: Vec<f64>,
    pub(crate) v: Vec<f64>,
    /// Per contact, along the dof: the impulse `Λ`, the forces `λ⁺`, `λ⁻`
    /// (on the velocity level the impulses `μ⁺`, `μ⁻`; zero where a contact closed).
    pub(crate) big: Vec<f64>,
    pub(crate) plus: Vec<f64>,
    pub(crate) minus: Vec<f64>,
    pub(crate) impact: bool,
    /// Whether the start's force problem held some contact (`λ⁺` or `μ⁺`
    /// nonzero before an impact drops it).
    pub(crate) held: bool,
    /// The change of `E_h` the identity of docs/theory.md §7.10 gives.
    de: f64,
    /// The force the scheme reports, per contact.
    lambda: Vec<f64>,
}

/// The step of §4.6.7, dense.
pub(crate) struct Oracle {
    m: Dense,
    minv: Dense,
    k: Dense,
    c: Option<Dense>,
    f: Vec<f64>,
    /// The forcing terms `(shape, A, ω)`: `A sin(ω t) shape` each.
    sines: Vec<(Vec<f64>, f64, f64)>,
    /// (dof, lo, hi, e).
    cons: Vec<(usize, f64, f64, f64)>,
    dt: f64,
    level: D1Level,
}

impl Oracle {
    pub(crate) fn new(dy: &Dynamics, e: f64, dt: f64) -> Self {
        let (m, k) = (dense(&dy.mass), dense(&dy.stiffness));
        let n = m.len();
        let cols: Vec<Vec<f64>> = (0..n).map(|j| solve(m.clone(), (0..n).map(|i| f64::from(u8::from(i == j))).collect())).collect();
        let minv = (0..n).map(|i| (0..n).map(|j| cols[j][i]).collect()).collect();
        let cons = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi, c.restitution.unwrap_or(e))).collect();
        let sines = dy
            .forcing
            .iter()
            .map(|f| match f.time {
                TimeProfile::Sine { amplitude, omega } => (f.shape.clone(), amplitude, omega),
                _ => panic!("the dense step takes Sine forcing terms"),
            })
            .collect();
        Self { m, minv, k, c: dy.damping.as_ref().map(dense), f: dy.load.clone(), sines, cons, dt, level: D1Level::Acceleration }
    }

    pub(crate) fn at(self, level: D1Level) -> Self {
        Self { level, ..self }
    }

    fn load(&self, t: f64) -> Vec<f64> {
        let mut f = self.f.clone();
        for (shape, a, w) in &self.sines {
            let s = a * (w * t).sin();
            f.iter_mut().zip(shape).for_each(|(f, g)| *f += s * g);
        }
        f
    }

    /// `M⁻¹(F(t) − K u − C v)`.
    fn acc(&self, t: f64, u: &[f64], v: &[f64]) -> Vec<f64> {
        let (ku, cv) = (mv(&self.k, u), self.c.as_ref().map_or(vec![0.0; u.len()], |c| mv(c, v)));
        let r: Vec<f64> = self.load(t).iter().zip(&ku).zip(&cv).map(|((f, k), c)| f - k - c).collect();
        mv(&self.minv, &r)
    }

    /// The problem on the contacts with the signs `s` (0: not in the set):
    /// `0 <= x ⊥ H(y + M⁻¹Hᵀx) + scale·H y >= 0`; returns `y + M⁻¹Hᵀx` and
    /// `x` along each dof (`s_i x_i`).
    fn solve_on(&self, s: &[f64], y: &[f64], extra: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let set: Vec<usize> = (0..s.len()).filter(|&i| s[i] != 0.0).collect();
        let mut along = vec![0.0; s.len()];
        if set.is_empty() {
            return (y.to_vec(), along);
        }
        let dof = |i: usize| self.cons[i].0;
        let w: Dense = set.iter().map(|&i| set.iter().map(|&j| s[i] * s[j] * self.minv[dof(i)][dof(j)]).collect()).collect();
        let q: Vec<f64> = set.iter().map(|&i| s[i] * y[dof(i)] * (1.0 + extra[i])).collect();
        let x = lcp(&w, &q);
        let mut out = y.to_vec();
        for (&i, xi) in set.iter().zip(&x) {
            along[i] = s[i] * xi;
            for (r, o) in out.iter_mut().enumerate() {
                *o += self.minv[r][dof(i)] * along[i];
            }
        }
        (out, along)
    }

    /// The start's index set `I₂ⁿ` from `(u, v)`.
    fn start_set(&self, u: &[f64], v: &[f64]) -> Vec<f64> {
        self.cons.iter().map(|&(c, lo, hi, _)| side(lo, hi, u[c])).zip(&self.cons).map(|(s, &(c, ..))| if s != 0.0 && s * v[c] <= TOL { s } else { 0.0 }).collect()
    }

    pub(crate) fn step(&self, u: &[f64], v: &[f64], n: usize) -> Step {
        match self.level {
            D1Level::Acceleration => self.step_acceleration(u, v, n),
            D1Level::Velocity => self.step_velocity(u, v, n),
        }
    }

    /// The velocity level, as Siconos writes it: `vfree = v + h a⁺_free`,
    /// `μ⁺` on the contacts closed at `u` (`H V₁ >= 0`), `q = u + h/2 (v + V₁)`;
    /// `I₁`, `I₂` (closed in the step) at `q`; with an impact the residual
    /// `−h/2 (a⁺_free + a⁻_free)`, else `−h/2 a⁺_free − ½M⁻¹Hᵀμ⁺ − h/2 a⁻_free`,
    /// `V_f = v − residual + M⁻¹Hᵀμ⁻` with `μ⁻` on `I₁` (`H V_f >= 0`); Newton's
    /// law on `I₁` with `V_f`.
    fn step_velocity(&self, u: &[f64], v: &[f64], n: usize) -> Step {
        let (h, k, nn) = (self.dt, self.cons.len(), u.len());
        let (t0, t1) = (n as f64 * h, (n + 1) as f64 * h);
        let zero = vec![0.0; k];
        let a0 = self.acc(t0, u, v);
        let vfree: Vec<f64> = (0..nn).map(|i| v[i] + h * a0[i]).collect();
        let start: Vec<f64> = self.cons.iter().map(|&(c, lo, hi, _)| side(lo, hi, u[c])).collect();
        let (v1, plus) = self.solve_on(&start, &vfree, &zero);
        let u1: Vec<f64> = (0..nn).map(|i| u[i] + 0.5 * h * (v[i] + v1[i])).collect();
        let closed: Vec<f64> = self.cons.iter().map(|&(c, lo, hi, _)| side(lo, hi, u1[c])).collect();
        let impact = self.cons.iter().zip(&closed).any(|(&(c, lo, hi, _), &s)| (s > 0.0 && u[c] - lo > TOL) || (s < 0.0 && hi - u[c] > TOL));
        let a1 = self.acc(t1, &u1, &v1);
        // M⁻¹Hᵀμ⁺ (along the dofs: Σ_i M⁻¹ e_{c_i} plus_i).
        let push: Vec<f64> = (0..nn).map(|r| self.cons.iter().zip(&plus).map(|(&(c, ..), p)| self.minv[r][c] * p).sum()).collect();
        let (vf, nu, minus) = if impact {
            ((0..nn).map(|i| v[i] + 0.5 * h * (a0[i] + a1[i])).collect::<Vec<f64>>(), zero.clone(), zero.clone())
        } else {
            let residual: Vec<f64> = (0..nn).map(|i| -0.5 * h * a0[i] - 0.5 * push[i] - 0.5 * h * a1[i]).collect();
            let free: Vec<f64> = (0..nn).map(|i| v[i] - residual[i]).collect();
            let (vf, minus) = self.solve_on(&closed, &free, &zero);
            let nu = plus.iter().zip(&minus).map(|(p, m)| 0.5 * p + m).collect();
            (vf, nu, minus)
        };
        let es: Vec<f64> = self.cons.iter().map(|c| c.3).collect();
        let (v2, big) = self.solve_on(&closed, &vf, &es);
        // §7.10, velocity level: ΔE_h = ½ Σν(vⁿ+V_f)_c + h/4 Σ(ν−μ⁺)(aⁿ+aⁿ⁺¹)_c + ½ ΣΛ(V_f+Vⁿ⁺¹)_c
        // (ν = μ⁺/2 + μ⁻ without impact, 0 with).
        let mut de = 0.0;
        for (i, &(c, ..)) in self.cons.iter().enumerate() {
            de += 0.5 * nu[i] * (v[c] + vf[c]) + 0.25 * h * (nu[i] - plus[i]) * (a0[c] + a1[c]) + 0.5 * big[i] * (vf[c] + v2[c]);
        }
        let lambda = big.iter().zip(&nu).map(|(b, n)| -(b + n) / h).collect();
        let held = plus.iter().any(|p| *p != 0.0);
        let plus = if impact { zero } else { plus };
        Step { u: u1, v: v2, big, plus, minus, impact, held, de, lambda }
    }

    fn step_acceleration(&self, u: &[f64], v: &[f64], n: usize) -> Step {
        let (h, k, nn) = (self.dt, self.cons.len(), u.len());
        let (t0, t1) = (n as f64 * h, (n + 1) as f64 * h);
        let zero = vec![0.0; k];
        let a0 = self.acc(t0, u, v);
        let (ap, plus) = self.solve_on(&self.start_set(u, v), &a0, &zero);
        let v1: Vec<f64> = (0..nn).map(|i| v[i] + h * ap[i]).collect();
        let u1: Vec<f64> = (0..nn).map(|i| u[i] + h * v[i] + 0.5 * h * h * ap[i]).collect();
        let closed: Vec<f64> = self.cons.iter().map(|&(c, lo, hi, _)| side(lo, hi, u1[c])).collect();
        let impact = self.cons.iter().zip(&closed).any(|(&(c, lo, hi, _), &s)| (s > 0.0 && u[c] - lo > TOL) || (s < 0.0 && hi - u[c] > TOL));
        let end: Vec<f64> = self.cons.iter().zip(&closed).map(|(&(c, ..), &s)| if s != 0.0 && s * v1[c] <= TOL { s } else { 0.0 }).collect();
        let a1 = self.acc(t1, &u1, &v1);
        let (vf, mplus, minus) = if impact {
            ((0..nn).map(|i| v[i] + 0.5 * h * (a0[i] + a1[i])).collect::<Vec<f64>>(), zero.clone(), zero.clone())
        } else {
            let (am, minus) = self.solve_on(&end, &a1, &zero);
            ((0..nn).map(|i| v[i] + 0.5 * h * (ap[i] + am[i])).collect(), plus.clone(), minus)
        };
        let es: Vec<f64> = self.cons.iter().map(|c| c.3).collect();
        let (v2, big) = self.solve_on(&closed, &vf, &es);
        // §7.10: ΔE_h = h/4 Σ(μ⁺+μ⁻)(vⁿ+V_f)_c + h²/8 Σ(μ⁺+μ⁻−2λ⁺)(aⁿ+aⁿ⁺¹)_c + ½ ΣΛ(V_f+Vⁿ⁺¹)_c
        // (along the dofs; μ± = λ± without impact, 0 with).
        let mut de = 0.0;
        for (i, &(c, ..)) in self.cons.iter().enumerate() {
            de += 0.25 * h * (mplus[i] + minus[i]) * (v[c] + vf[c]) + h * h / 8.0 * (mplus[i] + minus[i] - 2.0 * plus[i]) * (a0[c] + a1[c]) + 0.5 * big[i] * (vf[c] + v2[c]);
        }
        let held = plus.iter().any(|p| *p != 0.0);
        let plus = if impact { zero } else { plus };
        let lambda = (0..k).map(|i| -(big[i] + 0.5 * h * (plus[i] + minus[i])) / h).collect();
        Step { u: u1, v: v2, big, plus, minus, impact, held, de, lambda }
    }

    /// `E_h = ½VᵀMV + ½UᵀKU − FᵀU − h²/8 aᵀMa`, `a = M⁻¹(F − KU)` (steady load).
    fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let a = self.acc(0.0, u, &vec![0.0; u.len()]);
        0.5 * dot(&mv(&self.m, v), v) + 0.5 * dot(&mv(&self.k, u), u) - dot(&self.f, u) - self.dt * self.dt / 8.0 * dot(&mv(&self.m, &a), &a)
    }
}

/// The registry's row of `level`.
fn spec(level: D1Level, e: f64) -> SchemeSpec {
    match level {
        D1Level::Acceleration => SchemeSpec::d1_minus_linear(e),
        D1Level::Velocity => SchemeSpec::d1_minus_linear_velocity(e),
    }
}

/// The scheme on `dy` (damped problems through the constructor: the
/// registry refuses them).
fn build(level: D1Level, dy: Dynamics, e: f64, dt: f64, init: &Initial) -> Box<dyn Stepper> {
    if dy.damping.is_some() {
        return Box::new(D1MinusLinear::at_level(level, "d1".into(), dy, e, dt, init).unwrap());
    }
    spec(level, e).build(dy, dt, init).unwrap()
}

/// Step by step against the dense transcription, 150 steps, on lumped and
/// consistent masses, with and without damping, one and two contacts,
/// restitutions of the scheme and of each contact; positions, velocities,
/// and the reported mean force `−(Λ + dt/2(λ⁺ + λ⁻))/dt`.
#[test]
fn d1_minus_linear_follows_the_dense_step_step_by_step() {
    follow_the_dense_step(D1Level::Acceleration);
}

/// The same on the velocity level: the reported force
/// `−(Λ + μ⁺/2 + μ⁻)/dt` (`−Λ/dt` where a contact closed).
#[test]
fn d1_minus_linear_velocity_follows_the_dense_step_step_by_step() {
    follow_the_dense_step(D1Level::Velocity);
}

fn follow_the_dense_step(level: D1Level) {
    let mut rng = SplitMix64::new(2014);
    let (mut forces, mut impulses, mut impacts, mut worst) = (0usize, 0usize, 0usize, 0.0f64);
    for case in 0..24 {
        let (lumped, damped, two) = (case & 1 == 1, case & 2 == 2, case & 4 == 4);
        let (mut dy, init) = system(&mut rng, lumped, damped, two);
        let e = [0.0, 0.5, 1.0][case % 3];
        if case >= 8 {
            dy.contacts[0].restitution = Some(rng.next_f64());
        }
        let limit = spec(level, e).cfl_limit(&dy).unwrap().unwrap();
        let dt = limit * if damped { 0.2 } else { 0.3 + 0.6 * rng.next_f64() };
        let oracle = Oracle::new(&dy, e, dt).at(level);
        let mut s = build(level, dy, e, dt, &init);
        let (mut u, mut v) = (init.u.clone(), init.v.clone());
        for n in 0..150 {
            let o = oracle.step(&u, &v, n);
            s.step().unwrap();
            let st = s.state().unwrap();
            let scale = 1.0 + o.u.iter().chain(&o.v).fold(0.0f64, |m, x| m.max(x.abs()));
            for (i, (got, want)) in st.iter().zip(o.u.iter().chain(&o.v)).enumerate() {
                let err = (got - want).abs() / scale;
                worst = worst.max(err);
                assert!(err <= 1e-12, "{level:?}: case {case}, step {n}, state {i}: {got} vs {want}");
            }
            for (i, (got, want)) in s.contact_forces().iter().zip(&o.lambda).enumerate() {
                assert!((got - want).abs() <= 1e-10 * (1.0 + want.abs()), "{level:?}: case {case}, step {n}: λ_{i} {got} vs {want}");
            }
            forces += o.plus.iter().chain(&o.minus).filter(|x| **x != 0.0).count();
            impulses += o.big.iter().filter(|x| **x != 0.0).count();
            impacts += usize::from(o.impact);
            (u, v) = (o.u, o.v);
        }
    }
    // Not vacuous: contact forces, impulses and impact steps in many steps.
    assert!(forces > 200 && impulses > 30 && impacts > 30, "{level:?}: forces {forces}, impulses {impulses}, impacts {impacts}");
    eprintln!("d1-minus-linear ({level:?} level) vs the dense step: worst {worst:.1e}; {forces} contact forces, {impulses} impulses, {impacts} impact steps");
}

/// The parts of the force, `Λ`, `λ⁺` and `λ⁻` (`μ⁺`, `μ⁻` on the velocity
/// level) and the impact flag, against the dense step's at every step —
/// on the 24 random systems above, and on the two configurations where a
/// step with an impact (`I₃ ≠ ∅`) starts with a contact held by the start's
/// force problem, whose `λ⁺` the impact drops (no contact force in that
/// step): (a) two contacts, the first held on its stop by a steady load
/// while the second closes; (b) on the velocity level, one two-sided
/// contact whose stops are closer than a step's travel, held at the lower
/// one by `μ⁺` and closing on the upper one in the same step. Elsewhere
/// the reported mean force and the state do not read `λ⁺` in such a step
/// (the impact leaves out the smooth part) and the next step solves it
/// anew: these parts are where it shows.
#[test]
fn d1_minus_linear_force_parts_follow_the_dense_step() {
    for level in [D1Level::Acceleration, D1Level::Velocity] {
        let mut rng = SplitMix64::new(2014);
        let mut held_impacts = 0usize;
        let check = |dy: Dynamics, init: Initial, e: f64, dt: f64, steps: usize, what: &str| {
            let oracle = Oracle::new(&dy, e, dt).at(level);
            let mut s = D1MinusLinear::at_level(level, "d1".into(), dy, e, dt, &init).unwrap();
            let (mut u, mut v) = (init.u.clone(), init.v.clone());
            let mut held = 0usize;
            for n in 0..steps {
                let o = oracle.step(&u, &v, n);
                s.step().unwrap();
                let at = format!("{level:?}, {what}, step {n}");
                assert_eq!(s.impact(), o.impact, "{at}: impact");
                let (fp, fm) = s.forces();
                for (name, got, want) in [("Λ", s.impulses(), &o.big), ("λ⁺", fp, &o.plus), ("λ⁻", fm, &o.minus)] {
                    for (i, (g, w)) in got.iter().zip(want).enumerate() {
                        assert!((g - w).abs() <= 1e-10 * (1.0 + w.abs()), "{at}: {name}_{i} {g} vs the dense step's {w}");
                    }
                }
                held += usize::from(o.impact && o.held);
                (u, v) = (o.u, o.v);
            }
            held
        };
        for case in 0..24 {
            let (lumped, damped, two) = (case & 1 == 1, case & 2 == 2, case & 4 == 4);
            let (mut dy, init) = system(&mut rng, lumped, damped, two);
            let e = [0.0, 0.5, 1.0][case % 3];
            if case >= 8 {
                dy.contacts[0].restitution = Some(rng.next_f64());
            }
            let limit = spec(level, e).cfl_limit(&dy).unwrap().unwrap();
            let dt = limit * if damped { 0.2 } else { 0.3 + 0.6 * rng.next_f64() };
            held_impacts += check(dy, init, e, dt, 150, &format!("case {case}"));
        }
        // (a) The first contact held on its lower stop by the load, the
        // second (dof 3) thrown at its upper stop.
        let mut prev = held_impacts;
        for lumped in [true, false] {
            let (dy, _) = system(&mut SplitMix64::new(5), lumped, false, false);
            let lo = dy.contacts[0].bounds.lo;
            let load = vec![-2.0, 0.1, -0.2, 0.05];
            let mut u = vec![lo, 0.0, 0.0, 0.0];
            let k = dense(&dy.stiffness);
            let kf: Dense = (1..4).map(|i| (1..4).map(|j| k[i][j]).collect()).collect();
            u[1..].copy_from_slice(&solve(kf, (1..4).map(|i| load[i] - k[i][0] * lo).collect()));
            let contacts = vec![dy.contacts[0], Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: u[3] + 0.01 }, false)];
            let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), load, contacts);
            let dt = 0.4 * spec(level, 0.0).cfl_limit(&dy).unwrap().unwrap();
            for e in [0.0, 0.5] {
                held_impacts += check(dy.clone(), Initial { u: u.clone(), v: vec![0.0, 0.0, 0.0, 0.8] }, e, dt, 400, &format!("held and closing, lumped {lumped}, e = {e}"));
            }
        }
        assert!(held_impacts > prev, "{level:?}: (a) has no impact step with a held contact");
        prev = held_impacts;
        // (b) One contact between stops 2e-4 apart, pressed down by the load
        // while it moves up: μ⁺ holds it at the lower stop and the step's
        // travel dt/2 vⁿ closes the upper one. (The acceleration level
        // holds only contacts with ẏ <= 1e-8, which travel at most
        // dt·1e-8 in the step: not there.)
        if level == D1Level::Velocity {
            let (dy, _) = system(&mut SplitMix64::new(7), true, false, false);
            let contacts = vec![Contact::new(0, Bounds { lo: 0.0, hi: 2e-4 }, false)];
            let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), vec![-400.0, 0.0, 0.0, 0.0], contacts);
            let dt = 0.5 * spec(level, 0.0).cfl_limit(&dy).unwrap().unwrap();
            let v0 = 2.0 * 4e-4 / dt;
            for e in [0.0, 0.5, 1.0] {
                held_impacts += check(dy.clone(), Initial { u: vec![0.0; 4], v: vec![v0, 0.0, 0.0, 0.0] }, e, dt, 200, &format!("narrow stops, e = {e}"));
            }
            assert!(held_impacts > prev, "{level:?}: (b) has no impact step with a held contact");
        }
        eprintln!("d1-minus-linear ({level:?} level): {held_impacts} impact steps that started with a held contact");
    }
}

/// The discrete energy identity of docs/theory.md §7.10, steady load and
/// no damping: `E_h = ½VᵀMV + ½UᵀKU − FᵀU − dt²/8 aᵀMa` (computed here,
/// dense, on the scheme's states) changes by the contact terms the
/// identity names (from the oracle's multipliers); with one restitution
/// for all contacts the impact term is ≤ 0, and off contact `E_h` is
/// conserved.
#[test]
fn d1_minus_linear_keeps_its_discrete_energy_identity() {
    energy_identity(D1Level::Acceleration);
}

/// The velocity level's identity (docs/theory.md §7.10): the same `E_h`,
/// its change `½ Σν(Vⁿ + V_f)_c + dt/4 Σ(ν − μ⁺)(aⁿ + aⁿ⁺¹)_c` plus the
/// impulse's term, `ν = μ⁺/2 + μ⁻` (0 where a contact closed).
#[test]
fn d1_minus_linear_velocity_keeps_its_discrete_energy_identity() {
    energy_identity(D1Level::Velocity);
}

fn energy_identity(level: D1Level) {
    let mut rng = SplitMix64::new(95);
    let (mut worst, mut dissipating) = (0.0f64, 0);
    for case in 0..8 {
        let (dy, init) = system(&mut rng, case & 1 == 1, false, true);
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), dy.load.clone(), dy.contacts.clone());
        let n = dy.n();
        let e = [0.0, 0.3, 0.7, 1.0][case % 4];
        let dt = 0.5 * spec(level, e).cfl_limit(&dy).unwrap().unwrap();
        let oracle = Oracle::new(&dy, e, dt).at(level);
        let mut s = build(level, dy, e, dt, &init);
        let (mut u, mut v) = (init.u.clone(), init.v.clone());
        let mut e0 = oracle.energy(&u, &v);
        for step in 0..400 {
            let o = oracle.step(&u, &v, step);
            s.step().unwrap();
            let st = s.state().unwrap();
            (u, v) = (st[..n].to_vec(), st[n..].to_vec());
            let e1 = oracle.energy(&u, &v);
            let err = ((e1 - e0) - o.de).abs() / (1.0 + e0.abs());
            worst = worst.max(err);
            assert!(err <= 1e-12, "{level:?}: case {case}, step {step}: ΔE_h {} vs the identity's {}", e1 - e0, o.de);
            // The impact term alone: ½ ΣΛ(V_f + Vⁿ⁺¹)_c = −(1−e)/(2(1+e)) ΛᵀWΛ <= 0.
            if o.big.iter().all(|x| *x == 0.0) && o.plus.iter().chain(&o.minus).all(|x| *x == 0.0) {
                assert!((e1 - e0).abs() <= 1e-13 * (1.0 + e0.abs()), "{level:?}: case {case}, step {step}: off contact E_h moved {e0} -> {e1}");
            }
            dissipating += usize::from(o.big.iter().any(|x| *x != 0.0) && e < 1.0);
            e0 = e1;
        }
    }
    assert!(dissipating > 20, "{level:?}: only {dissipating} impulse steps");
    eprintln!("d1-minus-linear ({level:?} level) energy identity: worst {worst:.1e}, {dissipating} impulse steps with e < 1");
}

/// The cases a user meets first. (a) Starting in contact, held: from the
/// static state with the contact node on its stop under a load pressing it
/// there (solved here, densely, with the node fixed), the scheme stays at
/// rest for 2 000 steps and reports the static reaction as its force.
/// (b) Symmetric contacts reached together: a mirror-symmetric chain with
/// opposite stops at both ends and antisymmetric data stays antisymmetric,
/// both contacts engaging in the same steps, every step the dense step's.
#[test]
fn d1_minus_linear_held_starts_and_symmetric_contacts() {
    held_starts_and_symmetric_contacts(D1Level::Acceleration);
}

/// The same on the velocity level (held: `μ⁺ = dt r`, `μ⁻ = dt r/2`, so the
/// reported force `−(μ⁺/2 + μ⁻)/dt` is the reaction).
#[test]
fn d1_minus_linear_velocity_held_starts_and_symmetric_contacts() {
    held_starts_and_symmetric_contacts(D1Level::Velocity);
}

fn held_starts_and_symmetric_contacts(level: D1Level) {
    for lumped in [true, false] {
        let mut rng = SplitMix64::new(5);
        let (dy, _) = system(&mut rng, lumped, false, false);
        let n = dy.n();
        let lo = dy.contacts[0].bounds.lo;
        let mut load = vec![0.3, 0.1, -0.2, 0.05];
        load[0] = -2.0;
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), load.clone(), dy.contacts.clone());
        let k = dense(&dy.stiffness);
        let kf: Dense = (1..n).map(|i| (1..n).map(|j| k[i][j]).collect()).collect();
        let rf: Vec<f64> = (1..n).map(|i| load[i] - k[i][0] * lo).collect();
        let mut u_static = vec![lo];
        u_static.extend(solve(kf, rf));
        let reaction = mv(&k, &u_static)[0] - load[0];
        assert!(reaction > 0.0, "the load must press the node onto the stop");
        let dt = 0.5 * spec(level, 0.5).cfl_limit(&dy).unwrap().unwrap();
        let mut s = build(level, dy, 0.5, dt, &Initial { u: u_static.clone(), v: vec![0.0; n] });
        for step in 0..2000 {
            s.step().unwrap();
            let st = s.state().unwrap();
            for i in 0..n {
                assert!((st[i] - u_static[i]).abs() <= 1e-12 && st[n + i].abs() <= 1e-10, "{level:?}: lumped {lumped}, step {step}: left the static state: {st:?}");
            }
            let lam = s.contact_forces()[0];
            assert!((lam + reaction).abs() <= 1e-10 * (1.0 + reaction), "{level:?}: lumped {lumped}, step {step}: λ {lam} vs the static reaction −{reaction}");
        }
    }
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
    let oracle = Oracle::new(&dy, 1.0, dt).at(level);
    let mut s = build(level, dy, 1.0, dt, &init);
    let (mut u, mut v) = (init.u.clone(), init.v.clone());
    let mut together = 0;
    for step in 0..1000 {
        let o = oracle.step(&u, &v, step);
        s.step().unwrap();
        let st = s.state().unwrap();
        for (i, (a, b)) in st.iter().zip(o.u.iter().chain(&o.v)).enumerate() {
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{level:?}: step {step}, state {i}: {a} vs the dense step's {b}");
        }
        assert!((st[0] + st[3]).abs() <= 1e-13 && (st[1] + st[2]).abs() <= 1e-13, "{level:?}: step {step}: symmetry lost {st:?}");
        let f = s.contact_forces();
        assert_eq!(f[0] != 0.0, f[1] != 0.0, "{level:?}: step {step}: one contact engaged without its mirror: {f:?}");
        assert!((f[0] + f[1]).abs() <= 1e-10 * (1.0 + f[0].abs()), "{level:?}: step {step}: mirror forces {f:?}");
        together += usize::from(f[0] != 0.0);
        (u, v) = (o.u, o.v);
    }
    assert!(together > 12, "{level:?}: the two contacts engaged together in only {together} steps");
}

/// The limit is strict: on the lumped free bar the exact limit is the
/// closed form `2/sqrt(4c²/h²) = h/c` (the highest mode of the lumped P1
/// bar), and a step equal to it — the Courant-one step, which
/// `cd-taylor` takes — is refused (the stress study's runs there gained
/// ×10⁶ in energy through the contact steps), a step 1e-6 below it taken.
#[test]
fn d1_minus_linear_refuses_the_limit_itself() {
    use crate::common::bar_scene;
    use signorini_fem::BarMass;
    let m = 8;
    let (dy, _) = bar_scene(m, BarMass::Lumped, true, -0.01, -0.5, None);
    let init = Initial { u: vec![0.0; m + 1], v: vec![-1.0; m + 1] };
    let h = 1.0 / m as f64;
    for (level, e) in [(D1Level::Acceleration, 0.0), (D1Level::Acceleration, 1.0), (D1Level::Velocity, 0.0), (D1Level::Velocity, 1.0)] {
        let spec = spec(level, e);
        match spec.build(dy.clone(), h, &init) {
            Err(signorini_schemes::SchemeError::Unstable { limit, .. }) => assert!((limit - h).abs() <= 1e-12 * h, "limit {limit} against h/c = {h}"),
            Err(other) => panic!("{level:?}, e = {e}: dt = h/c refused for another reason: {other}"),
            Ok(_) => panic!("{level:?}, e = {e}: dt = h/c, the limit itself, accepted"),
        }
        assert!(spec.build(dy.clone(), h * (1.0 - 1e-6), &init).is_ok(), "{level:?}, e = {e}: a step just below the limit refused");
    }
}

/// A long run: the free lumped or consistent P1 bar (m = 20) under its
/// weight (body force −0.2) thrown at its floor, to t = 2 000 (8·10⁴ and
/// 1.4·10⁵ steps at half the limit), e = 0, ½, 1. On the velocity level a
/// closed contact's velocity is kept non-negative at both ends of every
/// step, so (one contact) its gap never decreases while it is closed: a
/// penetration made when it closes is never deepened; with e < 1 the energy
/// `E = ½VᵀMV + ½UᵀKU − FᵀU` never rises above its start (to 10⁻³). With
/// e = 1 it does not hold: the multipliers push on contacts that are
/// still penetrated and already separating (theory §7.10), and `E` grows
/// (printed: ×5–×6.5 by t = 2 000; ×40–×50 by t = 10⁴). The acceleration level on the same
/// lumped bar with e = ½ sinks through the floor: a resting contact
/// leaves its index set after each bounce (its rate `e w > ε`), so
/// each step moves the bar by the closed form `−dt² a_c/(2(1 + e))`,
/// `a_c = W/m₀` (W the bar's weight, m₀ the contact node's mass) — the
/// scheme's own behaviour, Siconos's as well (theory §4.6.7).
#[test]
fn d1_minus_linear_velocity_long_run_never_deepens_a_closed_contact() {
    use crate::common::bar_scene;
    use signorini_fem::BarMass;
    let (m, weight, gap) = (20, 0.2, -0.01);
    let mut closed_steps = 0usize;
    for mass in [BarMass::Lumped, BarMass::Std] {
        for e in [0.0, 0.5, 1.0] {
            let (dy, _) = bar_scene(m, mass, true, gap, -weight, None);
            let n = dy.n();
            let init = Initial { u: vec![0.0; n], v: vec![-0.5; n] };
            let sp = spec(D1Level::Velocity, e);
            let dt = 0.5 * sp.cfl_limit(&dy).unwrap().unwrap();
            let steps = (2000.0 / dt) as usize;
            let mut s = sp.build(dy.clone(), dt, &init).unwrap();
            let e0 = dy.energy(&init.u, &init.v);
            let (mut emax, mut y) = (e0, init.u[0] - gap);
            for step in 0..steps {
                s.step().unwrap();
                let y1 = s.displacement()[0] - gap;
                if y <= TOL {
                    closed_steps += 1;
                    assert!(y1 >= y - 1e-15, "{mass:?}, e = {e}, step {step}: a closed contact deepened {y} -> {y1}");
                }
                y = y1;
                if e < 1.0 || step % 64 == 0 {
                    let st = s.state().unwrap();
                    emax = emax.max(dy.energy(&st[..n], &st[n..]));
                }
            }
            if e < 1.0 {
                assert!(emax <= e0 * (1.0 + 1e-3), "{mass:?}, e = {e}: E rose to {emax} from {e0}");
            }
            eprintln!("d1-minus-linear-velocity({e}) {mass:?}, {steps} steps: E from {e0:.4} to at most {emax:.4}, gap at the end {y:.2e}");
        }
    }
    assert!(closed_steps > 100_000, "only {closed_steps} steps with the contact closed");
    // The acceleration level sinks (lumped: m₀ = h/2).
    let e = 0.5;
    let (dy, _) = bar_scene(m, BarMass::Lumped, true, gap, -weight, None);
    let n = dy.n();
    let sp = spec(D1Level::Acceleration, e);
    let dt = 0.5 * sp.cfl_limit(&dy).unwrap().unwrap();
    let mut s = sp.build(dy, dt, &Initial { u: vec![0.0; n], v: vec![-0.5; n] }).unwrap();
    for _ in 0..40_000 {
        s.step().unwrap();
    }
    // The mean over 20 000 steps (the bar's own vibration rides on it).
    let first = s.displacement()[0];
    for _ in 0..20_000 {
        s.step().unwrap();
    }
    let drift = (s.displacement()[0] - first) / 20_000.0;
    let a_c = weight / (0.5 / m as f64);
    let want = -dt * dt * a_c / (2.0 * (1.0 + e));
    assert!((drift - want).abs() <= 1e-4 * want.abs(), "the acceleration level's drift per step {drift} vs −dt² a_c/(2(1+e)) = {want}");
    eprintln!("d1-minus-linear({e}) lumped: sinks {drift:.6e} per step, the closed form {want:.6e}");
}
