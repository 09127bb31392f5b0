//! The CD-Lagrange scheme (Fekak, Brun, Gravouil, Depale, Comput. Mech.
//! 2017; Di Stasio, Dureisseix, Georges, Gravouil, Homolle, AMSES 2019;
//! docs/theory.md §4.6.9): the explicit central difference with half-step
//! velocities for the smooth part, the contacts closed at the new position
//! found from their gaps, and on them Newton's impact law on the velocity
//! level, enforced by Lagrange multipliers (impulses). With
//! `a(t, U) = M⁻¹(F(t) − K U)` and `H` the contacts' normals,
//!
//! ```text
//! U^{n+1}   = Uⁿ + dt V^{n+½}
//! I^{n+1}   = {contacts with y(U^{n+1}) <= 0}
//! V^{n+3/2} = V^{n+½} + dt a(t_{n+1}, U^{n+1}) + M⁻¹HᵀΛ^{n+1},
//!             0 <= Λ^{n+1} ⊥ H V^{n+3/2} + e H V^{n+½} >= 0   on I^{n+1}
//! ```
//!
//! with `y` each contact's gap (`u_c − lo` at a lower stop, `hi − u_c` at an
//! upper one; no tolerance), `e` the scheme's restitution (each contact's
//! own overriding it). The start is the central difference's half step
//! with the same law: `V^{½} = V⁰ + dt/2 a(0, U⁰) + M⁻¹HᵀΛ⁰`,
//! `0 <= Λ⁰ ⊥ H V^{½} + e H V⁰ >= 0` on `I⁰`. The positions are never
//! corrected: a contact may sit slightly past its stop (by at most one
//! step's travel), held there by the velocity law.
//!
//! The equations of the papers could not be read here (docs/theory.md
//! §4.6.9 says what was read and where): the step above is the algorithm
//! as the published comparisons that run it state it; where they differ
//! (the active set from the new gap, not a predicted one; the start)
//! the choice is ours and named.
//!
//! The steps are laid out as the two-step schemes': after `n` steps the
//! scheme holds `Uⁿ` and `V^{n−½}` (the velocity its next step starts
//! from; `V⁰` before the first step), the impulse `Λⁿ` belongs to `t_n` and
//! is reported (as `λ = −Λ/dt`, negative at a lower stop; `−Λ⁰/(dt/2)` for
//! the start's half step) after the step that used it, at `t_n`; the energy is the central difference's
//! `E^{n−½} = ½ V^{n−½}ᵀ M V^{n−½} + ½ Uⁿᵀ K U^{n−1} − Fᵀ(Uⁿ + U^{n−1})/2`
//! at `t_{n−½}` (theory §7.11: conserved off contact for a steady load,
//! changed at a contact step by `½ Λᵀ H (V^{n+½} + V^{n−½})`).
//!
//! Without contact the step is the central difference: stable for
//! `dt < 2/sqrt(κ_max)` of the pencil `(K, M)`, enforced strictly (at the
//! limit itself the highest mode is neutral, with a double eigenvalue −1).
//! One solve with `M` a step (a division with the lumped mass), one
//! product with `K`, and a contact solve with the influence columns of
//! `M⁻¹` on the closed contacts.

use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::onestep::{not_plain, with_avx2, Col, LumpedEnergy, LumpedTri};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, OneDof};
use signorini_fem::BandLdlt;

/// The CD-Lagrange scheme.
pub struct CdLagrange {
    label: String,
    restitution: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    /// `M`, factorised.
    mf: BandLdlt,
    /// The impact problem on the velocity level (influence columns of `M⁻¹`).
    impact_solve: MultiSolve,
    /// `Uⁿ` and `U^{n−1}` (`U⁰` before the first step).
    u: Vec<f64>,
    u_prev: Vec<f64>,
    /// `V^{n−½}` (`V⁰` before the first step).
    v: Vec<f64>,
    /// Scratch: `a(t_n, Uⁿ)`, then the velocity the law compares with.
    acc: Vec<f64>,
    v_old: Vec<f64>,
    loads: Loads,
    svals: Vec<f64>,
    /// Per contact, the side it is closed on at `Uⁿ`.
    closed: Vec<Active>,
    /// Per contact, the last step's impulse `Λ` along the dof.
    impulses: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// A lumped mass on the P1 bar: the step's fused pass ([`lumped_pass`]).
    lumped: Option<LumpedTri>,
    /// With `lumped`: the energy's sums in one pass.
    mass_tri: Option<LumpedEnergy>,
}

/// The step on a lumped mass and a tridiagonal `K` in one vectorised pass
/// (with at most one forcing term, `FORCED`): per row, `a = F − K U`
/// (`+ w g`), `x = a (1/D)` (`M⁻¹` as `BandLdlt::solve_in_place`'s
/// diagonal path, checked by [`not_plain`]), `V_new = V + kick x` into
/// `v_new` and, if `MOVE` (no contact closed: Newton's law changes
/// nothing), `U_new = U + dt V_new` into `u_new` — each row with the plain
/// step's operations in their order. False if some `x` is infinite, NaN
/// or `−0` (then the caller runs the plain step: `U`, `V` are untouched).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn lumped_pass<const FORCED: bool, const MOVE: bool, C: Col>(
    lt: &LumpedTri,
    [ksl, kdc, ksr, dc]: [C; 4],
    u: &[f64],
    load: &[f64],
    g: &[f64],
    w: f64,
    v: &[f64],
    kick: f64,
    h: f64,
    v_new: &mut [f64],
    u_new: &mut [f64],
) -> bool {
    let n = u.len();
    let l = n - 1;
    let (load, v, v_new, u_new, inv_d) = (&load[..n], &v[..n], &mut v_new[..n], &mut u_new[..n], &lt.inv_d[..n]);
    let row = |ku: f64, f: f64, gi: f64, s: f64, vi: f64, ui: f64| {
        let a = f - ku;
        let a = if FORCED { a + w * gi } else { a };
        let x = a * s;
        let vn = vi + kick * x;
        (x, vn, ui + h * vn)
    };
    let gi = |i: usize| if FORCED { g[i] } else { 0.0 };
    let (k0, kl) = lt.ku_ends(u);
    let (x0, v0, u0) = row(k0, load[0], gi(0), inv_d[0], v[0], u[0]);
    let (xl, vl, ul) = row(kl, load[l], gi(l), inv_d[l], v[l], u[l]);
    let mut odd = not_plain(x0) | not_plain(xl);
    (v_new[0], v_new[l]) = (v0, vl);
    if MOVE {
        (u_new[0], u_new[l]) = (u0, ul);
    }
    // The coefficient columns `cols` (slices or `Same`): [`LumpedTri::columns`].
    let (_, [um, uc, up], _) = lt.interior(u);
    let (fc, vc, gc) = (&load[1..l], &v[1..l], if FORCED { &g[1..l] } else { &g[..0] });
    let (vnc, unc) = (&mut v_new[1..l], &mut u_new[1..l]);
    for j in 0..n - 2 {
        let ku = ksl.at(j) * um[j] + kdc.at(j) * uc[j] + ksr.at(j) * up[j];
        let (x, vn, un) = row(ku, fc[j], if FORCED { gc[j] } else { 0.0 }, dc.at(j), vc[j], uc[j]);
        odd |= not_plain(x);
        vnc[j] = vn;
        if MOVE {
            unc[j] = un;
        }
    }
    odd == 0
}

/// The closed side of a contact at `x` (`None` if open): its gap `<= 0`.
fn side(lo: f64, hi: f64, x: f64) -> Active {
    if x <= lo {
        Active::Lower
    } else if x >= hi {
        Active::Upper
    } else {
        Active::None
    }
}

impl CdLagrange {
    /// Sets up the scheme (e ∈ [0, 1], each contact's own restitution
    /// overriding it; a massive contact node; time-dependent loads taken,
    /// damping refused).
    pub fn new(label: String, dy: Dynamics, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        crate::family::check("e", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped): the impulses act through M⁻¹" });
        }
        if dy.damping.is_some() {
            return Err(crate::family::not_taken(label, crate::family::Refused::Damping, " (an explicit step would need a solve with M + dt/2 C)"));
        }
        let n = dy.n();
        crate::check_start(dt, n, init)?;
        let mf = dy.mass.factor()?;
        let lumped = LumpedTri::new(&mf, &dy.stiffness);
        let impact_solve = MultiSolve::new(&dy, &mf)?.with_banded(dy.mass.clone())?;
        let k = dy.k();
        let mut loads = Loads::values(&dy, dt);
        let mut svals = vec![0.0; dy.forcing.len()];
        loads.next_into(&mut svals);
        Ok(Self {
            label,
            restitution,
            dt,
            n: 0,
            mf,
            impact_solve,
            u: init.u.clone(),
            u_prev: init.u.clone(),
            v: init.v.clone(),
            acc: vec![0.0; n],
            v_old: vec![0.0; n],
            loads,
            svals,
            closed: vec![Active::None; k],
            impulses: vec![0.0; k],
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            mass_tri: lumped.as_ref().and_then(|lt| LumpedEnergy::new(&dy.mass, lt)),
            lumped,
            dy,
        })
    }

    /// The step's first part on a lumped mass ([`lumped_pass`]): `V^{n+½}`
    /// before Newton's law into `v` (`V^{n−½}` into `v_old`) and, if `open`,
    /// `U^{n+1}` into `u` (`Uⁿ` into `u_prev`). False, nothing done, where
    /// the fused pass does not apply (no lumped mass, several forcing terms)
    /// or gives up (a product infinite, NaN or `−0`).
    fn fused_start(&mut self, kick: f64, open: bool) -> bool {
        let Some(lt) = &self.lumped else { return false };
        let (g, w) = match self.dy.forcing.as_slice() {
            [] => (&[][..], 0.0),
            [f] => (&f.shape[..], 1.0 * self.svals[0]),
            _ => return false,
        };
        let (u, load, v, v_new, u_new, h) = (&self.u[..], &self.dy.load[..], &self.v[..], &mut self.v_old[..], &mut self.u_prev[..], self.dt);
        let done = with_avx2!(lt.avx2, fn(lt: &LumpedTri, u: &[f64], load: &[f64], g: &[f64], w: f64, v: &[f64], kick: f64, h: f64, v_new: &mut [f64], u_new: &mut [f64], open: bool) -> bool {
            // A uniform mesh's coefficients as scalars (the same values: the same bits).
            match (g.is_empty(), open, lt.uniform) {
                (true, true, Some(c)) => lumped_pass::<false, true, _>(lt, c, u, load, g, w, v, kick, h, v_new, u_new),
                (true, true, None) => lumped_pass::<false, true, _>(lt, lt.columns(u.len()), u, load, g, w, v, kick, h, v_new, u_new),
                (true, false, Some(c)) => lumped_pass::<false, false, _>(lt, c, u, load, g, w, v, kick, h, v_new, u_new),
                (true, false, None) => lumped_pass::<false, false, _>(lt, lt.columns(u.len()), u, load, g, w, v, kick, h, v_new, u_new),
                (false, true, Some(c)) => lumped_pass::<true, true, _>(lt, c, u, load, g, w, v, kick, h, v_new, u_new),
                (false, true, None) => lumped_pass::<true, true, _>(lt, lt.columns(u.len()), u, load, g, w, v, kick, h, v_new, u_new),
                (false, false, Some(c)) => lumped_pass::<true, false, _>(lt, c, u, load, g, w, v, kick, h, v_new, u_new),
                (false, false, None) => lumped_pass::<true, false, _>(lt, lt.columns(u.len()), u, load, g, w, v, kick, h, v_new, u_new),
            }
        });
        if done {
            std::mem::swap(&mut self.v, &mut self.v_old);
            if open {
                std::mem::swap(&mut self.u, &mut self.u_prev);
            }
        }
        done
    }

    /// `V^{n−½}` (`V⁰` before the first step).
    pub fn half_step_velocity(&self) -> &[f64] {
        &self.v
    }

    /// Per contact, the last step's impulse `Λ` along the dof (positive
    /// pushes the dof up), at `t_{n−1}`.
    pub fn impulses(&self) -> &[f64] {
        &self.impulses
    }

    /// What [`CdLagrangeLockstep`](crate::CdLagrangeLockstep) takes of a
    /// single run (one rigid contact, after [`new`](Self::new)): the factor
    /// of `M`, and Newton's law as scalar arithmetic with its column
    /// `M⁻¹ e_c`; `None` with several contacts.
    pub(crate) fn lockstep_parts(&self) -> Option<(&BandLdlt, (OneDof, &[f64]))> {
        Some((&self.mf, self.impact_solve.one_dof()?))
    }

    /// `U^{n−1} = Uⁿ − dt V^{n−½}` (after `set_state`; the energy reads it).
    fn previous_from_velocity(&mut self) {
        let h = self.dt;
        for ((up, u), v) in self.u_prev.iter_mut().zip(&self.u).zip(&self.v) {
            *up = u - h * v;
        }
    }
}

impl Stepper for CdLagrange {
    stepper_accessors!();

    // `(Uⁿ, V^{n−½})` (`V⁰` before the first step); `U^{n−1}` (the
    // energy's) from them.
    displacement_velocity_state!(previous_from_velocity);

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        Some((self.impact_solve.pivoting_solves, self.impact_solve.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let h = self.dt;
        // The first step is the start's half step.
        let kick = if self.n == 0 { 0.5 * h } else { h };
        // Iⁿ from the gaps at Uⁿ.
        for (s, ct) in self.closed.iter_mut().zip(&self.dy.contacts) {
            *s = side(ct.bounds.lo, ct.bounds.hi, self.u[ct.dof]);
        }
        // None closed: Newton's law changes nothing, U moves in the same pass.
        let open = self.closed.iter().all(|s| *s == Active::None);
        let fused = self.fused_start(kick, open);
        if !fused {
            // a(t_n, Uⁿ) = M⁻¹(F(t_n) − K Uⁿ) (the load's values at t_n are in svals).
            self.dy.stiffness.mul_vec(&self.u, &mut self.acc);
            for (a, f) in self.acc.iter_mut().zip(&self.dy.load) {
                *a = f - *a;
            }
            add_terms(&mut self.acc, &self.dy.forcing, 1.0, &self.svals);
            self.mf.solve_in_place(&mut self.acc);
            // V_free = V^{n−½} + kick a; the law compares with V^{n−½}.
            self.v_old.copy_from_slice(&self.v);
            for (v, a) in self.v.iter_mut().zip(&self.acc) {
                *v += kick * a;
            }
        }
        // Newton's law on Iⁿ.
        self.impact_solve.newton_law(&self.dy.contacts, &self.closed, self.restitution, Some(&self.v_old), &mut self.v, &mut self.impulses)?;
        if !(fused && open) {
            // U^{n+1} = Uⁿ + dt V^{n+½}.
            std::mem::swap(&mut self.u_prev, &mut self.u);
            for ((u, up), v) in self.u.iter_mut().zip(&self.u_prev).zip(&self.v) {
                *u = up + h * v;
            }
        }
        self.loads.next_into(&mut self.svals);
        self.n += 1;
        let t = self.time();
        let t_lambda = (self.n - 1) as f64 * h;
        for i in 0..self.lams.len() {
            // The force over the kick the impulse completes (dt/2 at the start).
            self.lams[i] = -self.impulses[i] / kick;
            self.acts[i] = self.closed[i];
            let c = self.dy.contacts[i].dof;
            if !(self.u[c].is_finite() && self.v[c].is_finite() && self.lams[i].is_finite()) {
                return Err(SchemeError::NonFinite { step: self.n, time: t });
            }
        }
        Ok(StepReport { n: self.n, t, lambda: Some((t_lambda, self.lams[0])), active: self.acts[0] })
    }

    /// `E^{n−½} = ½ V^{n−½}ᵀ M V^{n−½} + ½ Uⁿᵀ K U^{n−1} − Fᵀ(Uⁿ + U^{n−1})/2`
    /// at `t_{n−½}` (the steady load `F`); `None` before the first step.
    fn energy(&mut self) -> Option<(f64, f64)> {
        if self.n == 0 {
            return None;
        }
        let (kin, pot, load) = if let (Some(lt), Some(me)) = (&self.lumped, &self.mass_tri) {
            // The three sums in one pass, the same bits (`acc`, scratch, is not written).
            me.sums(lt, &self.v, &self.u, Some(&self.u_prev), &self.dy.load, 0.5)
        } else {
            let kin = self.dy.mass.quad_form(&self.v);
            self.dy.stiffness.mul_vec(&self.u_prev, &mut self.acc);
            let pot: f64 = self.u.iter().zip(&self.acc).map(|(u, k)| u * k).sum();
            let load: f64 = self.dy.load.iter().zip(self.u.iter().zip(&self.u_prev)).map(|(f, (u, up))| f * 0.5 * (u + up)).sum();
            (kin, pot, load)
        };
        Some((self.time() - 0.5 * self.dt, 0.5 * kin + 0.5 * pot - load))
    }
}

// ---- The registry's row of this file: cd-lagrange.

use crate::family::{check, kappa_bound, Capabilities, Family, Node, Param, SchemeSpec};

/// The restitution `e`.
const E: Param = Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: None };

/// The CD-Lagrange scheme (central difference, impulses on the velocity
/// level by Lagrange multipliers), e ∈ [0, 1].
pub(crate) static CD_LAGRANGE: Family = Family {
    name: "cd-lagrange",
    about: "CD-Lagrange (Fekak–Brun–Gravouil–Depale 2017; Di Stasio et al. 2019): explicit central difference with half-step velocities, contacts closed at the new position, Newton's impact law on the velocity level by Lagrange multipliers, positions never corrected (docs/theory.md §4.6.9)",
    params: &[E],
    presets: &[],
    validate: |a| check("e", a[0], (0.0..=1.0).contains(&a[0]), "[0, 1]"),
    capabilities: |_| Capabilities { explicit: true, node: Node::Massive, damping: false, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, dy| Ok(Some(2.0 / kappa_bound(&dy.stiffness, &dy.mass)?.sqrt())),
    stability_rule: |_| Some("explicit central difference: dt < 2/sqrt(κ_max) of the pencil (K, M), strictly (at the limit itself the highest mode is neutral)"),
    build: |s, dy, dt, init| {
        s.check_cfl(&dy, dt, false)?;
        if !s.limit_waived() {
            if let Some(limit) = s.cfl_limit(&dy)? {
                if dt >= limit * (1.0 - 1e-9) {
                    return Err(SchemeError::Unstable { dt, limit, scheme: s.to_string(), rule: s.stability_rule().unwrap_or("") });
                }
            }
        }
        Ok(Box::new(CdLagrange::new(s.to_string(), dy, s.args()[0], dt, init)?))
    },
};

impl SchemeSpec {
    /// The CD-Lagrange scheme with restitution `e` (not validated until built).
    pub fn cd_lagrange(restitution: f64) -> Self {
        CD_LAGRANGE.with(&[restitution])
    }
}
