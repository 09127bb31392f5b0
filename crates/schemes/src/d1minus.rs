//! The time-discontinuous Galerkin scheme of Schindler and Acary
//! (Math. Comput. Simul. 95 (2014) 180–199; docs/theory.md §4.6.7), in
//! Siconos's half-explicit form on the acceleration level
//! (`D1MinusLinearOSI` with `TimeSteppingD1Minus`): the velocity is
//! piecewise linear and discontinuous at the levels, the position
//! continuous; the non-impulsive contact forces are computed on the
//! acceleration level at both ends of the step for the contacts that are
//! closed with vanishing velocity, the impulses on the velocity level by
//! Newton's law at the step's end. With `a(t, U, V) = M⁻¹(F(t) − K U − C V)`
//! and `H` the contacts' normals,
//!
//! ```text
//! a⁺   = a(t_n, Uⁿ, Vⁿ) + M⁻¹Hᵀλ⁺,   0 <= λ⁺ ⊥ H a⁺ >= 0       on I₂ⁿ
//! V₁   = Vⁿ + dt a⁺,   Uⁿ⁺¹ = Uⁿ + dt/2 (Vⁿ + V₁)
//! I₁ = {y(Uⁿ⁺¹) <= ε},  I₂ = I₁ ∩ {ẏ(V₁) <= ε},  I₃ = I₁ ∩ {y(Uⁿ) > ε}
//! no contact closed in the step (I₃ = ∅):
//!     a⁻ = a(t_{n+1}, Uⁿ⁺¹, V₁) + M⁻¹Hᵀλ⁻,   0 <= λ⁻ ⊥ H a⁻ >= 0  on I₂
//!     V_f = Vⁿ + dt/2 (a⁺ + a⁻)
//! a contact closed in the step (I₃ ≠ ∅): no contact force in the step,
//!     V_f = Vⁿ + dt/2 (a(t_n, Uⁿ, Vⁿ) + a(t_{n+1}, Uⁿ⁺¹, V₁))
//! Vⁿ⁺¹ = V_f + M⁻¹HᵀΛ,   0 <= Λ ⊥ H Vⁿ⁺¹ + e H V_f >= 0           on I₁
//! ```
//!
//! with `y` each contact's gap (`u_c − lo` at a lower stop, `hi − u_c` at
//! an upper one), `ẏ` its rate, `I₂ⁿ` the closed contacts with `ẏ(Vⁿ) <= ε`
//! at the start, and Siconos's threshold `ε = 1e-8` ([`INDEX_SET_TOLERANCE`],
//! absolute, in the problem's units). Each complementarity problem is a
//! box problem on the contact dofs with the influence columns of `M⁻¹`,
//! solved exactly. The contact force reported at `t_{n+1}` is the step's
//! mean, `λ = −(Λ + dt/2 (λ⁺ + λ⁻))/dt` (the impulse alone in a step where a
//! contact closed), signed as the other schemes' (negative at a lower stop);
//! [`D1MinusLinear::impulses`] and [`D1MinusLinear::forces`] give the parts.
//!
//! Without contact and without damping the step is the velocity Verlet
//! (central difference) scheme: explicit, stable for `dt < 2/sqrt(κ_max)`.
//! The damping force enters explicitly (`a` is evaluated at the predicted
//! `V₁`), which lowers that limit by an amount not certified here: the
//! registry refuses a damping matrix; [`D1MinusLinear::new`] takes one
//! (Siconos's `LagrangianLinearTIDS` with `C`, for the comparison).
//! When `I₂` is empty at the end of a step without impact, `λ⁻ = 0`
//! (Siconos then keeps the last force it computed, `λ⁺`; the two agree on
//! every step of the stored comparisons).
//!
//! **The velocity level** ([`D1Level::Velocity`], the registry's
//! `d1-minus-linear-velocity(e)`; Siconos's
//! `halfexplicit_velocity_level`) keeps the step and the impact problem and
//! puts the non-impulsive contact forces on the velocity level, as impulses
//! `μ±` on every closed contact (no condition on the rate):
//!
//! ```text
//! V₁   = Vⁿ + dt a(t_n, Uⁿ, Vⁿ) + M⁻¹Hᵀμ⁺,   0 <= μ⁺ ⊥ H V₁ >= 0          on I₁ⁿ
//! Uⁿ⁺¹ = Uⁿ + dt/2 (Vⁿ + V₁),   I₁, I₃ as above
//! I₃ = ∅:  V_f = ½(Vⁿ + V₁) + dt/2 a(t_{n+1}, Uⁿ⁺¹, V₁) + M⁻¹Hᵀμ⁻,
//!          0 <= μ⁻ ⊥ H V_f >= 0                                         on I₁
//! I₃ ≠ ∅:  V_f = Vⁿ + dt/2 (a(t_n, Uⁿ, Vⁿ) + a(t_{n+1}, Uⁿ⁺¹, V₁))
//! Vⁿ⁺¹ = V_f + M⁻¹HᵀΛ,   0 <= Λ ⊥ H Vⁿ⁺¹ + e H V_f >= 0                   on I₁
//! ```
//!
//! (`I₁ⁿ` the contacts closed at `Uⁿ`; `½(Vⁿ + V₁)` carries half of `μ⁺`
//! into `V_f`, as Siconos's residual does). Without an impact `H V_f >= 0`
//! on `I₁` already, so `Λ = 0`; the force reported is
//! `λ = −(Λ + μ⁺/2 + μ⁻)/dt`, the step's contact impulse over `dt`
//! (the impulse alone where a contact closed); [`D1MinusLinear::forces`]
//! gives `μ⁺` and `μ⁻` (impulses) on this level.

use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::onestep::{not_plain, with_avx2, Col, LumpedEnergy, LumpedTri};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, OneDof};
use signorini_fem::BandLdlt;

/// Siconos's threshold of the index sets (`DEFAULT_TOL_D1MINUS`): a
/// contact is closed when its gap is at most this, its velocity vanishing
/// when its rate is at most this (absolute).
pub const INDEX_SET_TOLERANCE: f64 = 1e-8;

/// Where the half-explicit step of [`D1MinusLinear`] puts its
/// non-impulsive contact forces (Siconos's `D1MinusLinearOSI` types).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum D1Level {
    /// `halfexplicit_acceleration_level` (Siconos's default): forces
    /// `λ±` with `H a >= 0` on the closed contacts with vanishing rate.
    Acceleration,
    /// `halfexplicit_velocity_level`: impulses `μ±` with `H V >= 0` on
    /// the closed contacts.
    Velocity,
}

/// Schindler and Acary's time-discontinuous Galerkin scheme, half-explicit
/// on the acceleration level or on the velocity level ([`D1Level`]).
pub struct D1MinusLinear {
    label: String,
    level: D1Level,
    restitution: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    /// `M`, factorised.
    mf: BandLdlt,
    /// The force problems (acceleration level) and the impact problem
    /// (velocity level), both with the influence columns of `M⁻¹`.
    force_solve: MultiSolve,
    impact_solve: MultiSolve,
    u: Vec<f64>,
    v: Vec<f64>,
    /// `a(t_n, Uⁿ, Vⁿ)` (kept from the last step's `a(t_{n+1}, Uⁿ⁺¹, V₁)` when undamped).
    a_free: Vec<f64>,
    /// `a⁺`, then `a⁻`; `a(t_{n+1}, Uⁿ⁺¹, V₁)`.
    acc: Vec<f64>,
    a_end: Vec<f64>,
    v1: Vec<f64>,
    /// `C V` (damped problems only).
    ctmp: Vec<f64>,
    /// Per contact, the side of the start's force problem (`I₂ⁿ` on the
    /// acceleration level, `I₁ⁿ` on the velocity level).
    start: Vec<Active>,
    /// Per contact, the side of `I₁` and of the end's force problem (`I₂`
    /// on the acceleration level, `I₁` on the velocity level).
    closed: Vec<Active>,
    end: Vec<Active>,
    loads: Loads,
    s_old: Vec<f64>,
    s_new: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// Per contact, the last step's `Λ`, `λ⁺` and `λ⁻` (`μ⁺`, `μ⁻` on the
    /// velocity level), along the dof.
    impulses: Vec<f64>,
    f_plus: Vec<f64>,
    f_minus: Vec<f64>,
    /// Whether the last step had a contact close (`I₃ ≠ ∅`).
    impact: bool,
    /// A lumped mass on the P1 bar, undamped: the step's fused passes
    /// ([`predict_pass`], [`end_pass`]).
    lumped: Option<LumpedTri>,
    /// With `lumped`: the energy's sums in one pass.
    mass_tri: Option<LumpedEnergy>,
}

/// The start of the step on a lumped mass when no force problem acts at
/// its start: per row, `V₁ = Vⁿ + dt a(t_n)` into `v1` and `Uⁿ⁺¹ = Uⁿ +
/// dt/2 (Vⁿ + V₁)` into `u`, in one vectorised pass with the plain step's
/// operations.
#[inline(always)]
fn predict_pass(a_free: &[f64], v: &[f64], h: f64, v1: &mut [f64], u: &mut [f64]) {
    let n = u.len();
    let (a_free, v, v1) = (&a_free[..n], &v[..n], &mut v1[..n]);
    for i in 0..n {
        let w = v[i] + h * a_free[i];
        v1[i] = w;
        u[i] += 0.5 * h * (v[i] + w);
    }
}

/// The end of the step on a lumped mass and a tridiagonal `K` (undamped,
/// at most one forcing term, `FORCED`) when no force problem acts at its
/// end, in one vectorised pass: per row `a_end = M⁻¹(F(t_{n+1}) − K Uⁿ⁺¹
/// (+ w g))` (`M⁻¹` as `BandLdlt::solve_in_place`'s diagonal path, checked
/// by [`not_plain`]) into `a_end`, and `V_f` into `out`: `Vⁿ + dt/2 (a0 +
/// a_end)` or, `VEL` (the velocity level without impact), `½(Vⁿ + V₁) +
/// dt/2 a_end` — the plain step's operations in their order. False if
/// some product is infinite, NaN or `−0` (`v`, `a0`, `v1` untouched:
/// the plain end runs instead).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn end_pass<const FORCED: bool, const VEL: bool, C: Col>(
    lt: &LumpedTri,
    [ksl, kdc, ksr, dc]: [C; 4],
    u: &[f64],
    load: &[f64],
    g: &[f64],
    w: f64,
    v: &[f64],
    a0: &[f64],
    v1: &[f64],
    h: f64,
    a_end: &mut [f64],
    out: &mut [f64],
) -> bool {
    let n = u.len();
    let l = n - 1;
    let (load, v, a_end, out, inv_d) = (&load[..n], &v[..n], &mut a_end[..n], &mut out[..n], &lt.inv_d[..n]);
    // Only the form's own input is read (`a0` or `v1`).
    let (a0, v1) = if VEL { (&v1[..0], &v1[..n]) } else { (&a0[..n], &a0[..0]) };
    let row = |ku: f64, f: f64, gi: f64, s: f64, vi: f64, a0i: f64, v1i: f64| {
        let a = f - ku;
        let a = if FORCED { a + w * gi } else { a };
        let x = a * s;
        let vf = if VEL { 0.5 * (vi + v1i) + 0.5 * h * x } else { vi + 0.5 * h * (a0i + x) };
        (x, vf)
    };
    let gi = |i: usize| if FORCED { g[i] } else { 0.0 };
    let a0i = |i: usize| if VEL { 0.0 } else { a0[i] };
    let v1i = |i: usize| if VEL { v1[i] } else { 0.0 };
    let (k0, kl) = lt.ku_ends(u);
    let (x0, f0) = row(k0, load[0], gi(0), inv_d[0], v[0], a0i(0), v1i(0));
    let (xl, fl) = row(kl, load[l], gi(l), inv_d[l], v[l], a0i(l), v1i(l));
    let mut odd = not_plain(x0) | not_plain(xl);
    (a_end[0], a_end[l], out[0], out[l]) = (x0, xl, f0, fl);
    // The coefficient columns (slices or `Same`): [`LumpedTri::columns`].
    let (_, [um, uc, up], _) = lt.interior(u);
    let (fc, vc) = (&load[1..l], &v[1..l]);
    let gc = if FORCED { &g[1..l] } else { &g[..0] };
    let ac = if VEL { &a0[..0] } else { &a0[1..l] };
    let v1c = if VEL { &v1[1..l] } else { &v1[..0] };
    let (ec, oc) = (&mut a_end[1..l], &mut out[1..l]);
    for j in 0..n - 2 {
        let ku = ksl.at(j) * um[j] + kdc.at(j) * uc[j] + ksr.at(j) * up[j];
        let (x, vf) = row(ku, fc[j], if FORCED { gc[j] } else { 0.0 }, dc.at(j), vc[j], if VEL { 0.0 } else { ac[j] }, if VEL { v1c[j] } else { 0.0 });
        odd |= not_plain(x);
        ec[j] = x;
        oc[j] = vf;
    }
    odd == 0
}

/// The closed side of a contact at `x` (`None` if open).
pub(crate) fn side(lo: f64, hi: f64, x: f64) -> Active {
    if x - lo <= INDEX_SET_TOLERANCE {
        Active::Lower
    } else if hi - x <= INDEX_SET_TOLERANCE {
        Active::Upper
    } else {
        Active::None
    }
}

/// `out = M⁻¹(F(t) − K u − C v)`, `svals` the forcing terms' values at `t`.
fn accel(dy: &Dynamics, mf: &BandLdlt, svals: &[f64], u: &[f64], v: &[f64], out: &mut [f64], ctmp: &mut [f64]) {
    dy.stiffness.mul_vec(u, out);
    for (o, f) in out.iter_mut().zip(&dy.load) {
        *o = f - *o;
    }
    add_terms(out, &dy.forcing, 1.0, svals);
    if let Some(c) = &dy.damping {
        c.mul_vec(v, ctmp);
        out.iter_mut().zip(ctmp.iter()).for_each(|(o, c)| *o -= c);
    }
    mf.solve_in_place(out);
}

impl D1MinusLinear {
    /// Sets up the scheme on the acceleration level (e ∈ [0, 1], each
    /// contact's own restitution overriding it; a massive contact node;
    /// damping and time-dependent loads taken, the damping explicitly).
    pub fn new(label: String, dy: Dynamics, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        Self::at_level(D1Level::Acceleration, label, dy, restitution, dt, init)
    }

    /// Sets up the scheme on the given level (otherwise as [`D1MinusLinear::new`]).
    pub fn at_level(level: D1Level, label: String, dy: Dynamics, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        crate::family::check("e", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped): the contact forces and impulses act through M⁻¹" });
        }
        let n = dy.n();
        crate::check_start(dt, n, init)?;
        let mf = dy.mass.factor()?;
        let lumped = if dy.damping.is_none() { LumpedTri::new(&mf, &dy.stiffness) } else { None };
        let force_solve = MultiSolve::new(&dy, &mf)?.with_banded(dy.mass.clone())?;
        let impact_solve = MultiSolve::new(&dy, &mf)?.with_banded(dy.mass.clone())?;
        let k = dy.k();
        let mut loads = Loads::values(&dy, dt);
        let mut s_old = vec![0.0; dy.forcing.len()];
        loads.next_into(&mut s_old);
        let mut me = Self {
            label,
            level,
            restitution,
            dt,
            n: 0,
            mf,
            force_solve,
            impact_solve,
            u: init.u.clone(),
            v: init.v.clone(),
            a_free: vec![0.0; n],
            acc: vec![0.0; n],
            a_end: vec![0.0; n],
            v1: vec![0.0; n],
            ctmp: vec![0.0; if dy.damping.is_some() { n } else { 0 }],
            start: vec![Active::None; k],
            closed: vec![Active::None; k],
            end: vec![Active::None; k],
            s_new: s_old.clone(),
            s_old,
            loads,
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            impulses: vec![0.0; k],
            f_plus: vec![0.0; k],
            f_minus: vec![0.0; k],
            impact: false,
            mass_tri: lumped.as_ref().and_then(|lt| LumpedEnergy::new(&dy.mass, lt)),
            lumped,
            dy,
        };
        me.refresh();
        Ok(me)
    }

    /// From `Uⁿ, Vⁿ`: `a(t_n, Uⁿ, Vⁿ)` and the start's index set.
    fn refresh(&mut self) {
        accel(&self.dy, &self.mf, &self.s_old, &self.u, &self.v, &mut self.a_free, &mut self.ctmp);
        self.start_set();
    }

    /// The start's index set from `Uⁿ, Vⁿ`: the closed contacts with
    /// `ẏ <= ε` (`I₂ⁿ`, acceleration level), or all closed ones (`I₁ⁿ`,
    /// velocity level).
    fn start_set(&mut self) {
        for (s, ct) in self.start.iter_mut().zip(&self.dy.contacts) {
            let rate = self.v[ct.dof];
            *s = match side(ct.bounds.lo, ct.bounds.hi, self.u[ct.dof]) {
                Active::Lower if self.level == D1Level::Velocity || rate <= INDEX_SET_TOLERANCE => Active::Lower,
                Active::Upper if self.level == D1Level::Velocity || -rate <= INDEX_SET_TOLERANCE => Active::Upper,
                _ => Active::None,
            };
        }
    }

    /// The level the contact forces are computed on.
    pub fn level(&self) -> D1Level {
        self.level
    }

    /// Velocity `Vⁿ`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// Per contact, the last step's impulse `Λ` along the dof (positive
    /// pushes the dof up).
    pub fn impulses(&self) -> &[f64] {
        &self.impulses
    }

    /// Per contact, the last step's forces `λ⁺` (at `t_n`) and `λ⁻` (at
    /// `t_{n+1}`) along the dof — on the velocity level the impulses `μ⁺`
    /// and `μ⁻`; zeros in a step where a contact closed.
    pub fn forces(&self) -> (&[f64], &[f64]) {
        (&self.f_plus, &self.f_minus)
    }

    /// Whether a contact closed in the last step (`I₃ ≠ ∅`: no contact
    /// force, the impulse alone).
    pub fn impact(&self) -> bool {
        self.impact
    }

    /// What [`D1MinusLinearLockstep`](crate::D1MinusLinearLockstep) takes
    /// of a single run (one rigid contact, after [`at_level`](Self::at_level)):
    /// the factor of `M`, and the contact solve as scalar arithmetic with
    /// its column `M⁻¹ e_c` (the force and impact problems' alike: the
    /// same bits); `None` with several contacts.
    pub(crate) fn lockstep_parts(&self) -> Option<(&BandLdlt, (OneDof, &[f64]))> {
        Some((&self.mf, self.impact_solve.one_dof()?))
    }

    /// `a(t_n, Uⁿ, Vⁿ)` (the lockstep engine takes the start's).
    pub(crate) fn free_acceleration(&self) -> &[f64] {
        &self.a_free
    }

    /// The end of the step in one pass ([`end_pass`]): `a(t_{n+1}, Uⁿ⁺¹)`
    /// into `a_end`, `V_f` into `v` (by a swap with the buffer it was made
    /// in: `acc` on the velocity level, which does not use it, `v1` on the
    /// acceleration level, where `V₁` is no longer needed), the force
    /// problem's multipliers zero. False, nothing done, where it does not
    /// apply (no lumped mass, several forcing terms, a force problem at the
    /// end) or gives up (a product infinite, NaN or `−0`).
    fn fused_end(&mut self, impact: bool, fast_start: bool) -> bool {
        let Some(lt) = &self.lumped else { return false };
        if !impact && self.end.iter().any(|s| *s != Active::None) {
            return false;
        }
        let (g, w) = match self.dy.forcing.as_slice() {
            [] => (&[][..], 0.0),
            [f] => (&f.shape[..], 1.0 * self.s_new[0]),
            _ => return false,
        };
        let vel = self.level == D1Level::Velocity && !impact;
        let (u, load, v, h) = (&self.u[..], &self.dy.load[..], &self.v[..], self.dt);
        let done = if vel {
            let (v1, a_end, out) = (&self.v1[..], &mut self.a_end[..], &mut self.acc[..]);
            with_avx2!(lt.avx2, fn(lt: &LumpedTri, u: &[f64], load: &[f64], g: &[f64], w: f64, v: &[f64], v1: &[f64], h: f64, a_end: &mut [f64], out: &mut [f64]) -> bool {
                if g.is_empty() {
                    match lt.uniform {
                        Some(c) => end_pass::<false, true, _>(lt, c, u, load, g, w, v, v1, v1, h, a_end, out),
                        None => end_pass::<false, true, _>(lt, lt.columns(u.len()), u, load, g, w, v, v1, v1, h, a_end, out),
                    }
                } else {
                    match lt.uniform {
                        Some(c) => end_pass::<true, true, _>(lt, c, u, load, g, w, v, v1, v1, h, a_end, out),
                        None => end_pass::<true, true, _>(lt, lt.columns(u.len()), u, load, g, w, v, v1, v1, h, a_end, out),
                    }
                }
            })
        } else {
            // a⁺ = a(t_n) where no force acted at the start, and with an impact.
            let a0 = if impact || fast_start { &self.a_free[..] } else { &self.acc[..] };
            let (a_end, out) = (&mut self.a_end[..], &mut self.v1[..]);
            with_avx2!(lt.avx2, fn(lt: &LumpedTri, u: &[f64], load: &[f64], g: &[f64], w: f64, v: &[f64], a0: &[f64], h: f64, a_end: &mut [f64], out: &mut [f64]) -> bool {
                if g.is_empty() {
                    match lt.uniform {
                        Some(c) => end_pass::<false, false, _>(lt, c, u, load, g, w, v, a0, a0, h, a_end, out),
                        None => end_pass::<false, false, _>(lt, lt.columns(u.len()), u, load, g, w, v, a0, a0, h, a_end, out),
                    }
                } else {
                    match lt.uniform {
                        Some(c) => end_pass::<true, false, _>(lt, c, u, load, g, w, v, a0, a0, h, a_end, out),
                        None => end_pass::<true, false, _>(lt, lt.columns(u.len()), u, load, g, w, v, a0, a0, h, a_end, out),
                    }
                }
            })
        };
        if done {
            std::mem::swap(&mut self.v, if vel { &mut self.acc } else { &mut self.v1 });
            self.f_minus.iter_mut().for_each(|x| *x = 0.0);
            if impact {
                self.f_plus.iter_mut().for_each(|x| *x = 0.0);
            }
        }
        done
    }

    /// The end of the step as written (module docs): `a(t_{n+1}, Uⁿ⁺¹,
    /// V₁)`, then `V_f` with the force problem at the end (no impact).
    fn plain_end(&mut self, impact: bool, velocity_level: bool, fast_start: bool) -> Result<(), SchemeError> {
        let h = self.dt;
        // a(t_{n+1}, Uⁿ⁺¹, V₁).
        accel(&self.dy, &self.mf, &self.s_new, &self.u, &self.v1, &mut self.a_end, &mut self.ctmp);
        if impact {
            // No contact force: V_f = Vⁿ + h/2 (a(t_n) + a(t_{n+1})).
            for ((v, a0), a1) in self.v.iter_mut().zip(&self.a_free).zip(&self.a_end) {
                *v += 0.5 * h * (a0 + a1);
            }
            self.f_plus.iter_mut().chain(self.f_minus.iter_mut()).for_each(|x| *x = 0.0);
        } else if velocity_level {
            // V_f = ½(Vⁿ + V₁) + h/2 a(t_{n+1}) + M⁻¹Hᵀμ⁻ on I₁.
            for ((v, v1), a1) in self.v.iter_mut().zip(&self.v1).zip(&self.a_end) {
                *v = 0.5 * (*v + v1) + 0.5 * h * a1;
            }
            Self::force_problem(&mut self.force_solve, &self.end, &mut self.v, &mut self.f_minus)?;
        } else {
            // a⁻ = a(t_{n+1}) + M⁻¹Hᵀλ⁻ on I₂ (into v1: V₁ is no longer needed), V_f = Vⁿ + h/2 (a⁺ + a⁻).
            // (a⁺ = a(t_n) where no force problem acted at the start.)
            self.v1.copy_from_slice(&self.a_end);
            Self::force_problem(&mut self.force_solve, &self.end, &mut self.v1, &mut self.f_minus)?;
            let a_plus = if fast_start { &self.a_free } else { &self.acc };
            for ((v, a0), a1) in self.v.iter_mut().zip(a_plus).zip(&self.v1) {
                *v += 0.5 * h * (a0 + a1);
            }
        }
        Ok(())
    }

    /// The force problem on `acc` (an acceleration, or on the velocity
    /// level a velocity) with the sides `sides` (skipped when none is
    /// closed): `acc += M⁻¹Hᵀx`, `0 <= x ⊥ H acc >= 0`, the multipliers
    /// into `out`.
    fn force_problem(ms: &mut MultiSolve, sides: &[Active], acc: &mut [f64], out: &mut [f64]) -> Result<(), SchemeError> {
        if sides.iter().all(|s| *s == Active::None) {
            out.iter_mut().for_each(|x| *x = 0.0);
            return Ok(());
        }
        for (i, s) in sides.iter().enumerate() {
            (ms.lo[i], ms.hi[i]) = match s {
                Active::Lower => (0.0, f64::INFINITY),
                Active::Upper => (f64::NEG_INFINITY, 0.0),
                Active::None => (f64::NEG_INFINITY, f64::INFINITY),
            };
        }
        let (mu, _) = ms.solve(acc)?;
        out.copy_from_slice(mu);
        Ok(())
    }
}

impl Stepper for D1MinusLinear {
    stepper_accessors!();

    // `Uⁿ, Vⁿ`; `a(t_n, Uⁿ, Vⁿ)` and `I₂ⁿ` are recomputed from them.
    displacement_velocity_state!(refresh);

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        let (f, i) = (&self.force_solve, &self.impact_solve);
        Some((f.pivoting_solves + i.pivoting_solves, f.pivots + i.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let h = self.dt;
        self.loads.next_into(&mut self.s_new);
        let velocity_level = self.level == D1Level::Velocity;
        // On a lumped mass with no force problem at the start: V₁ and Uⁿ⁺¹ in
        // one pass after the index sets (V₁ at the contacts by the same
        // operations first).
        let fast_start = self.lumped.is_some() && self.start.iter().all(|s| *s == Active::None);
        if fast_start {
        } else if velocity_level {
            // V₁ = Vⁿ + h a(t_n, Uⁿ, Vⁿ) + M⁻¹Hᵀμ⁺ on I₁ⁿ.
            for ((v1, v), a) in self.v1.iter_mut().zip(&self.v).zip(&self.a_free) {
                *v1 = v + h * a;
            }
            Self::force_problem(&mut self.force_solve, &self.start, &mut self.v1, &mut self.f_plus)?;
        } else {
            // a⁺ = a(t_n, Uⁿ, Vⁿ) + M⁻¹Hᵀλ⁺ on I₂ⁿ.
            self.acc.copy_from_slice(&self.a_free);
            Self::force_problem(&mut self.force_solve, &self.start, &mut self.acc, &mut self.f_plus)?;
            // V₁ = Vⁿ + h a⁺.
            for ((v1, v), a) in self.v1.iter_mut().zip(&self.v).zip(&self.acc) {
                *v1 = v + h * a;
            }
        }
        // The index sets at the step's end (I₃ from Uⁿ, before U moves on).
        let mut impact = false;
        for (i, ct) in self.dy.contacts.iter().enumerate() {
            let c = ct.dof;
            // (No force problem at the start: λ⁺ = μ⁺ = 0, and V₁ as the pass makes it.)
            let v1c = if fast_start { self.v[c] + h * self.a_free[c] } else { self.v1[c] };
            let x1 = self.u[c] + 0.5 * h * (self.v[c] + v1c);
            let s = side(ct.bounds.lo, ct.bounds.hi, x1);
            self.closed[i] = s;
            let (old_gap, rate) = match s {
                Active::Lower => (self.u[c] - ct.bounds.lo, v1c),
                Active::Upper => (ct.bounds.hi - self.u[c], -v1c),
                Active::None => (0.0, 0.0),
            };
            if s != Active::None && old_gap > INDEX_SET_TOLERANCE {
                impact = true;
            }
            // The end's force problem: I₂ (acceleration level), I₁ (velocity level).
            self.end[i] = if s != Active::None && (velocity_level || rate <= INDEX_SET_TOLERANCE) { s } else { Active::None };
        }
        if fast_start {
            self.f_plus.iter_mut().for_each(|x| *x = 0.0);
            let (a_free, v, v1, u) = (&self.a_free[..], &self.v[..], &mut self.v1[..], &mut self.u[..]);
            with_avx2!(self.lumped.as_ref().is_some_and(|l| l.avx2), fn(a_free: &[f64], v: &[f64], h: f64, v1: &mut [f64], u: &mut [f64]) -> () {
                predict_pass(a_free, v, h, v1, u)
            });
        } else {
            // Uⁿ⁺¹ = Uⁿ + h/2 (Vⁿ + V₁).
            for ((u, v), v1) in self.u.iter_mut().zip(&self.v).zip(&self.v1) {
                *u += 0.5 * h * (v + v1);
            }
        }
        // a(t_{n+1}, Uⁿ⁺¹, V₁) and V_f: in one pass on a lumped mass where no
        // force problem acts at the end.
        if !self.fused_end(impact, fast_start) {
            self.plain_end(impact, velocity_level, fast_start)?;
        }
        // Newton's law on I₁: Vⁿ⁺¹ = V_f + M⁻¹HᵀΛ.
        self.impact_solve.newton_law(&self.dy.contacts, &self.closed, self.restitution, None, &mut self.v, &mut self.impulses)?;
        self.impact = impact;
        std::mem::swap(&mut self.s_old, &mut self.s_new);
        // The next step's a(t_n, Uⁿ, Vⁿ): undamped, a(t_{n+1}, Uⁿ⁺¹) itself.
        if self.dy.damping.is_none() {
            std::mem::swap(&mut self.a_free, &mut self.a_end);
            self.start_set();
        } else {
            self.refresh();
        }
        self.n += 1;
        for i in 0..self.lams.len() {
            let smooth = match (impact, velocity_level) {
                (true, _) => 0.0,
                (false, false) => 0.5 * h * (self.f_plus[i] + self.f_minus[i]),
                (false, true) => 0.5 * self.f_plus[i] + self.f_minus[i],
            };
            self.lams[i] = -(self.impulses[i] + smooth) / h;
        }
        self.acts.copy_from_slice(&self.closed);
        crate::contact_step_report(self.n, self.time(), &self.dy.contacts, &self.u, Some(&self.v), &self.lams, &self.acts)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        if let (Some(lt), Some(me)) = (&self.lumped, &self.mass_tri) {
            // `Dynamics::energy`'s three sums in one pass, the same bits.
            let (kin, pot, load) = me.sums(lt, &self.v, &self.u, None, &self.dy.load, 1.0);
            return Some((self.time(), 0.5 * kin + 0.5 * pot - load));
        }
        Some((self.time(), self.dy.energy(&self.u, &self.v)))
    }
}

// ---- The registry's rows of this file: d1-minus-linear, d1-minus-linear-velocity.

use crate::family::{check, kappa_bound, Capabilities, Family, Node, Param, SchemeSpec};

/// The restitution `e`.
const E: Param = Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: None };

/// The stability rule of both levels (the same smooth part).
const RULE: &str =
    "half-explicit (velocity Verlet without contact): dt < 2/sqrt(κ_max) of the pencil (K, M), strictly (at the limit itself the highest mode is neutral and the contact steps excite it)";

/// Both rows' builder: the limit checked, strictly, then the scheme on `level`.
fn build_at(level: D1Level, s: &SchemeSpec, dy: Dynamics, dt: f64, init: &Initial) -> Result<Box<dyn crate::Stepper>, SchemeError> {
    s.check_cfl(&dy, dt, false)?;
    // Strictly below the limit, unlike the Courant-one central
    // difference: at dt = 2/sqrt(κ_max) (the lumped free bar at
    // dx/dt = 1) the highest mode has the double eigenvalue −1 and the
    // contact steps feed it — the stress study's runs there gained
    // ×10⁶ in energy (theory §4.6.7).
    if !s.limit_waived() {
        if let Some(limit) = s.cfl_limit(&dy)? {
            if dt >= limit * (1.0 - 1e-9) {
                return Err(SchemeError::Unstable { dt, limit, scheme: s.to_string(), rule: s.stability_rule().unwrap_or("") });
            }
        }
    }
    Ok(Box::new(D1MinusLinear::at_level(level, s.to_string(), dy, s.args()[0], dt, init)?))
}

/// Schindler and Acary's time-discontinuous Galerkin scheme (Siconos's
/// `D1MinusLinearOSI`, half-explicit on the acceleration level), e ∈ [0, 1].
pub(crate) static D1_MINUS_LINEAR: Family = Family {
    name: "d1-minus-linear",
    about: "time-discontinuous Galerkin (Schindler–Acary 2014; Siconos's D1MinusLinearOSI, half-explicit on the acceleration level): explicit velocity Verlet smooth part, contact forces at both ends of the step on the closed contacts with vanishing velocity, Newton's impact law at velocity level (docs/theory.md §4.6.7)",
    params: &[E],
    presets: &[],
    validate: |a| check("e", a[0], (0.0..=1.0).contains(&a[0]), "[0, 1]"),
    capabilities: |_| Capabilities { explicit: true, node: Node::Massive, damping: false, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, dy| Ok(Some(2.0 / kappa_bound(&dy.stiffness, &dy.mass)?.sqrt())),
    stability_rule: |_| Some(RULE),
    build: |s, dy, dt, init| build_at(D1Level::Acceleration, s, dy, dt, init),
};

/// The same scheme half-explicit on the velocity level (Siconos's
/// `halfexplicit_velocity_level`), e ∈ [0, 1].
pub(crate) static D1_MINUS_LINEAR_VELOCITY: Family = Family {
    name: "d1-minus-linear-velocity",
    about: "time-discontinuous Galerkin as d1-minus-linear, half-explicit on the velocity level (Siconos's D1MinusLinearOSI halfexplicit_velocity_level): contact impulses at both ends of the step keep the closed contacts' velocities non-negative, Newton's impact law at velocity level (docs/theory.md §4.6.7)",
    build: |s, dy, dt, init| build_at(D1Level::Velocity, s, dy, dt, init),
    ..D1_MINUS_LINEAR
};

impl SchemeSpec {
    /// Schindler and Acary's scheme with restitution `e` (not validated until built).
    pub fn d1_minus_linear(restitution: f64) -> Self {
        D1_MINUS_LINEAR.with(&[restitution])
    }

    /// Its velocity-level variant with restitution `e` (not validated until built).
    pub fn d1_minus_linear_velocity(restitution: f64) -> Self {
        D1_MINUS_LINEAR_VELOCITY.with(&[restitution])
    }
}
