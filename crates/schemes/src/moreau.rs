//! Moreau–Jean time stepping (docs/theory.md §4.6.4; the scheme of Siconos): a θ-scheme
//! on velocities with Newton's impact law at the velocity level,
//!
//! ```text
//! M (V^{n+1} - V^n) + dt K (U^n + θ dt V^{n+θ}) = dt F + p e_c,
//! U^{n+1} = U^n + dt V^{n+θ},   V^{n+θ} = (1-θ) V^n + θ V^{n+1},
//! if the contact is predicted active (u_c^n + γ dt v_c^n <= g; γ = 1/2 by default):
//!     0 <= v_c^{n+1} + e v_c^n  ⊥  p >= 0,   else p = 0,
//! ```
//!
//! i.e. `(M + θ²dt²K) V^{n+1} = M V^n - dt K U^n - θ(1-θ) dt² K V^n + dt F + p e_c`,
//! one solve and the closed-form projection on `v_c^{n+1}`. The impulse `p`
//! is reported as the mean force `λ = -p/dt` at `t_{n+1}`. The constraint
//! holds at the velocity level only: `u_c` may dip below `g` by O(dt·v).
//!
//! A time-dependent load (the terms of [`crate::Dynamics::forcing`]) enters
//! as its exact impulse over the step, `dt F` → `dt F_s + Σ_j shape_j ∫_{t_n}^{t_{n+1}} s_j`
//! (`dt` times the exact mean [`crate::TimeProfile::mean`]; Moreau's
//! measure form `M dV = F dt + dP` integrated exactly), which keeps the
//! θ = 1/2 scheme second order for a smooth load.
//!
//! Damping ([`crate::Dynamics::damping`]) acts on the same mid-velocity,
//! `+ dt C V^{n+θ}` on the left: the step matrix is `M + θ dt C + θ² dt² K`
//! and the right-hand side gains `- (1-θ) dt C V^n`.
//!
//! Energy (θ = 1/2, steady F): `ΔE = p (v_c^n + v_c^{n+1})/2 = (1-e)/2 p v_c^n`
//! (by the complementarity): zero for e = 1, `≤ 0` for an approaching node,
//! but a gain when the predicted-active node is already separating
//! (`v_c^n > 0`) and the impulse holds it — the velocity-level law's price.

use crate::fused::{fused_switches, FusedSwitch};
use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::stabilized::{neighbours, tridiagonal_forward_dispatch, TriRows};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, Projection};
use signorini_fem::BandLdlt;

/// The Moreau–Jean scheme.
pub struct MoreauJean {
    label: String,
    theta: f64,
    restitution: f64,
    /// The activation predictor's weight: a contact is predicted active when
    /// `u_c + γ dt v_c` reaches its bound (Siconos's `MoreauJeanOSI(θ, γ)`).
    gamma: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    a: BandLdlt,
    proj: Projection,
    u: Vec<f64>,
    v: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    ktmp: Vec<f64>,
    impulse: f64,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// Several contacts: the exact solve on the velocities.
    multi: Option<MultiSolve>,
    /// Per forcing term, its exact means over the steps (a [`crate::Sampler`] each).
    loads: Loads,
    /// Their latest means.
    svals: Vec<f64>,
    /// A persistent index set with thresholds (Siconos's
    /// `MoreauJeanDirectProjectionOSI`) instead of the plain prediction.
    index_set: Option<IndexSet>,
    /// The bar's free velocity fused ([`Tridiagonal`]), if it applies, and its switches.
    fused: FusedSwitch<Tridiagonal>,
    /// Per forcing term, `dt` times its mean (`add_terms`' weights).
    s_w: Vec<f64>,
}

/// The P1 bar's free velocity fused (`M`, `K` and the factor of `A`
/// tridiagonal, `L` not the identity, no damping): the right-hand side
/// `M V + dt (F − K (U + θ(1−θ) dt V)) + Σ_j dt m_j g_j` made row by row
/// inside the forward sweep of the solve (the shared
/// [`tridiagonal_forward`](crate::stabilized::tridiagonal_forward), as
/// `contact-stabilized`'s), `U + θ(1−θ) dt V` computed where a row needs it
/// instead of in a pass of its own, then the factor's backward sweep.
/// Every value is the general path's operations in the same order (its
/// pass, `SymBand::mul_vec`'s tridiagonal rows, the sum, `add_terms`,
/// `BandLdlt::solve_in_place`'s sweeps), so the same bits (cost:
/// `crates/run/benches/step.rs`, `implicit_scheme_step`).
type Tridiagonal = crate::stabilized::TriPair;

/// [`Tridiagonal`] of an undamped `dy` (`M`, `K`) beside the factor `a`.
fn fused_step(dy: &Dynamics, a: &BandLdlt) -> Option<Tridiagonal> {
    dy.damping.is_none().then_some(())?;
    Tridiagonal::beside(&dy.mass, &dy.stiffness, a)
}

/// [`Tridiagonal`]'s rows for one step: `M v + dt (f − K (u + c v))`, `c = θ(1−θ) dt`.
struct MjRows<'a> {
    t: &'a Tridiagonal,
    dt: f64,
    c: f64,
    u: &'a [f64],
    v: &'a [f64],
    f: &'a [f64],
}

impl TriRows for MjRows<'_> {
    #[inline(always)]
    fn interior(&self, a: usize, o: &mut [f64]) {
        let len = o.len();
        let (u, v, c, dt) = (self.u, self.v, self.c, self.dt);
        let (ul, uc, ur) = neighbours(u, a, len);
        let (vl, vc, vr) = neighbours(v, a, len);
        let (msl, mdc, msr) = self.t.m.window(a, len);
        let (ksl, kdc, ksr) = self.t.k.window(a, len);
        let fr = &self.f[a..a + len];
        for j in 0..len {
            let mv = msl[j] * vl[j] + mdc[j] * vc[j] + msr[j] * vr[j];
            let kt = ksl[j] * (ul[j] + c * vl[j]) + kdc[j] * (uc[j] + c * vc[j]) + ksr[j] * (ur[j] + c * vr[j]);
            o[j] = mv + dt * (fr[j] - kt);
        }
    }

    #[inline(always)]
    fn edge(&self, i: usize) -> f64 {
        let (u, v, n) = (self.u, self.v, self.u.len());
        let mv = self.t.m.row(n, i, |j| v[j]);
        let kt = self.t.k.row(n, i, |j| u[j] + self.c * v[j]);
        mv + self.dt * (self.f[i] - kt)
    }
}

/// The contacts' sides predicted active, kept from step to step with
/// Siconos's thresholds (`MoreauJeanDirectProjectionOSI`'s index set 1):
/// a side whose predicted gap `y + γ dt ẏ` (`y = u_c − lo` at a lower
/// bound, `hi − u_c` at an upper one, `ẏ` its rate) is `<= enter` joins;
/// a member leaves when `y + γ dt ẏ > leave` and `ẏ >= 0`.
#[derive(Clone, Debug)]
pub(crate) struct IndexSet {
    pub(crate) enter: f64,
    pub(crate) leave: f64,
    /// Per contact, its lower and its upper side in the set.
    pub(crate) sides: Vec<(bool, bool)>,
    /// The sides are set by the caller ([`MoreauJean::with_given_index_set`]):
    /// the step uses them as they are.
    pub(crate) given: bool,
}

impl IndexSet {
    fn keep(member: bool, y: f64, ydot: f64, enter: f64, leave: f64) -> bool {
        if member {
            !(y > leave && ydot >= 0.0)
        } else {
            y <= enter
        }
    }
}

impl MoreauJean {
    /// Sets up the scheme (needs a massive contact node; θ ∈ [1/2, 1], e ∈ [0, 1],
    /// the activation predictor's γ ∈ [0, 1]).
    pub fn new(label: String, dy: Dynamics, theta: f64, restitution: f64, gamma: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped): the impact law acts on its velocity" });
        }
        let n = dy.n();
        crate::check_start(dt, n, init)?;
        let a_mat = dy.step_matrix(theta * dt, theta * theta * dt * dt);
        let a = a_mat.factor()?;
        let c = dy.contact().dof;
        let k = dy.k();
        let multi = if k > 1 { Some(MultiSolve::new(&dy, &a)?.with_banded(a_mat)?) } else { None };
        let mut w = vec![0.0; n];
        w[c] = 1.0;
        a.solve_in_place(&mut w);
        let proj = Projection::new(c, w)?;
        let (loads, svals) = (Loads::means(&dy, dt), vec![0.0; dy.forcing.len()]);
        let fused = FusedSwitch::new(fused_step(&dy, &a));
        Ok(Self {
            label,
            theta,
            restitution,
            gamma,
            dt,
            n: 0,
            a,
            proj,
            u: init.u.clone(),
            v: init.v.clone(),
            rhs: vec![0.0; n],
            tmp: vec![0.0; n],
            ktmp: vec![0.0; n],
            impulse: 0.0,
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            multi,
            loads,
            svals,
            index_set: None,
            fused,
            s_w: vec![0.0; dy.forcing.len()],
            dy,
        })
    }

    /// Keeps the predicted-active sides as a persistent index set with
    /// thresholds ([`IndexSet`]) instead of predicting afresh each step.
    pub(crate) fn with_index_set(mut self, enter: f64, leave: f64) -> Self {
        self.index_set = Some(IndexSet { enter, leave, sides: vec![(false, false); self.dy.k()], given: false });
        self
    }

    /// The sides with Newton's law are chosen by the caller
    /// ([`Self::index_set_parts`]), not predicted: a step uses them as set.
    pub(crate) fn with_given_index_set(mut self) -> Self {
        self.index_set = Some(IndexSet { enter: 0.0, leave: 0.0, sides: vec![(false, false); self.dy.k()], given: true });
        self
    }

    /// `U^n`, the contacts and the index set, if kept (to be chosen with
    /// [`Self::with_given_index_set`], read by a position projection).
    pub(crate) fn index_set_parts(&mut self) -> Option<(&mut [f64], &[crate::Contact], &mut IndexSet)> {
        let set = self.index_set.as_mut()?;
        Some((&mut self.u, &self.dy.contacts, set))
    }

    /// `U^n, V^n` and the step count, to redo a step from its start
    /// ([`Self::free_velocity`] computed once, then [`Self::finish_step`]).
    pub(crate) fn step_start_mut(&mut self) -> (&mut [f64], &mut [f64], &mut usize) {
        (&mut self.u, &mut self.v, &mut self.n)
    }

    /// The unconstrained `V^{n+1}` of the step ([`Self::free_velocity`]'s
    /// result, consumed by [`Self::finish_step`]).
    pub(crate) fn free_mut(&mut self) -> &mut [f64] {
        &mut self.rhs
    }

    /// The mechanical energy of the current state (what [`Stepper::energy`]
    /// reports; the projections' energy bookkeeping reads it too).
    pub(crate) fn energy_now(&self) -> f64 {
        self.dy.energy(&self.u, &self.v)
    }

    /// Contact `i`'s lower and upper sides predicted active at the start of
    /// the step: `u_c + γ dt v_c <= lo` (`>= hi`), or the index set's rule.
    fn predict(&mut self, i: usize) -> (bool, bool) {
        let ct = &self.dy.contacts[i];
        let (uc, vc) = (self.u[ct.dof], self.v[ct.dof]);
        let pred = uc + self.gamma * self.dt * vc;
        match &mut self.index_set {
            None => (pred <= ct.bounds.lo, pred >= ct.bounds.hi),
            Some(s) if s.given => s.sides[i],
            Some(s) => {
                let (lo, hi) = s.sides[i];
                let lo = IndexSet::keep(lo, pred - ct.bounds.lo, vc, s.enter, s.leave);
                let hi = IndexSet::keep(hi, ct.bounds.hi - pred, -vc, s.enter, s.leave);
                s.sides[i] = (lo, hi);
                (lo, hi)
            }
        }
    }

    /// Velocity `V^n`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// Several contacts: each contact predicted active at its lower
    /// (upper) stop, `u_c + γ dt v_c <= lo` (`>= hi`), gets Newton's law
    /// `v_c^{n+1} >= -e_i v_c^n` (`<=`); the others are free; one exact
    /// solve for all (`rhs` holds the unconstrained `V^{n+1}`).
    fn finish_multi(&mut self) -> Result<StepReport, SchemeError> {
        let (dt, th) = (self.dt, self.theta);
        for i in 0..self.dy.k() {
            let (at_lo, at_hi) = self.predict(i);
            let ct = &self.dy.contacts[i];
            let vc = self.v[ct.dof];
            let e = ct.restitution.unwrap_or(self.restitution);
            let ms = self.multi.as_mut().expect("several contacts");
            ms.lo[i] = if at_lo { -e * vc } else { f64::NEG_INFINITY };
            ms.hi[i] = if at_hi { -e * vc } else { f64::INFINITY };
            if ms.lo[i] > ms.hi[i] {
                // Both stops predicted active (a gap below γ dt v): the lower wins.
                ms.hi[i] = f64::INFINITY;
            }
        }
        let ms = self.multi.as_mut().expect("several contacts");
        let (mu, st) = ms.solve(&mut self.rhs)?;
        for (i, (&m, &a)) in mu.iter().zip(st).enumerate() {
            self.lams[i] = -m / dt;
            self.acts[i] = a;
        }
        for ((u, v), vn) in self.u.iter_mut().zip(self.v.iter_mut()).zip(&self.rhs) {
            *u += dt * ((1.0 - th) * *v + th * vn);
            *v = *vn;
        }
        self.impulse = -self.lams[0] * dt;
        self.n += 1;
        crate::contact_step_report(self.n, self.time(), &self.dy.contacts, &self.u, None, &self.lams, &self.acts)
    }

    /// The impulse `p` of the last step.
    pub fn impulse(&self) -> f64 {
        self.impulse
    }
}

impl Stepper for MoreauJean {
    stepper_accessors!();

    displacement_velocity_state!();

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        self.multi.as_ref().map(|m| (m.pivoting_solves, m.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        self.free_velocity();
        self.finish_step()
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), self.energy_now()))
    }
}

impl MoreauJean {
    fused_switches!(fused);

    /// The step's unconstrained `V^{n+1}`, left in `rhs` (the forcing
    /// terms' means advance: once a step).
    pub(crate) fn free_velocity(&mut self) {
        let (dt, th) = (self.dt, self.theta);
        if let Some(tri) = self.fused.active() {
            // The same right-hand side and solve, fused ([`Tridiagonal`]).
            self.loads.next_into(&mut self.svals);
            for (w, s) in self.s_w.iter_mut().zip(&self.svals) {
                *w = dt * s;
            }
            let (l, _) = self.a.tridiagonal_factors().expect("tridiagonal");
            let rows = MjRows { t: tri, dt, c: th * (1.0 - th) * dt, u: &self.u, v: &self.v, f: &self.dy.load };
            tridiagonal_forward_dispatch(tri.avx2, &rows, &self.dy.forcing, &[&self.s_w], &[], l, &mut self.rhs);
            self.a.backward_in_place(&mut self.rhs);
            return;
        }
        // rhs = M V - dt K (U + θ(1-θ) dt V) + dt F
        self.dy.mass.mul_vec(&self.v, &mut self.rhs);
        for ((t, u), v) in self.tmp.iter_mut().zip(&self.u).zip(&self.v) {
            *t = u + th * (1.0 - th) * dt * v;
        }
        self.dy.stiffness.mul_vec(&self.tmp, &mut self.ktmp);
        for ((b, k), f) in self.rhs.iter_mut().zip(&self.ktmp).zip(&self.dy.load) {
            *b += dt * (f - k);
        }
        // + Σ_j shape_j ∫ s_j over [t_n, t_{n+1}] (exact impulse of each forcing term).
        // (the means over [t_n, t_{n+1}]).
        self.loads.next_into(&mut self.svals);
        add_terms(&mut self.rhs, &self.dy.forcing, dt, &self.svals);
        if let Some(cm) = &self.dy.damping {
            // - (1-θ) dt C V^n
            cm.mul_vec(&self.v, &mut self.ktmp);
            let w = (1.0 - th) * dt;
            self.rhs.iter_mut().zip(&self.ktmp).for_each(|(b, k)| *b -= w * k);
        }
        self.a.solve_in_place(&mut self.rhs);
    }

    /// The rest of the step from the unconstrained `V^{n+1}` in `rhs`:
    /// Newton's law on the sides predicted (or given), `U^{n+1}, V^{n+1}`.
    pub(crate) fn finish_step(&mut self) -> Result<StepReport, SchemeError> {
        let (dt, th) = (self.dt, self.theta);
        let c = self.dy.contact().dof;
        if self.multi.is_some() {
            return self.finish_multi();
        }
        let vc = self.v[c];
        // The contact predicted active at its lower (upper) stop gets
        // Newton's law v_c^{n+1} >= -e v_c^n (<=); both predicted (a gap
        // below γ dt |v|): the lower wins, as in `finish_multi`.
        let (at_lo, at_hi) = self.predict(0);
        let e = self.dy.contact().restitution.unwrap_or(self.restitution);
        let (p, active) = if at_lo {
            let pr = self.proj.project(&mut self.rhs, -e * vc, f64::INFINITY);
            (pr.mu, pr.active)
        } else if at_hi {
            let pr = self.proj.project(&mut self.rhs, f64::NEG_INFINITY, -e * vc);
            (pr.mu, pr.active)
        } else {
            (0.0, Active::None)
        };
        // U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1}); V^{n+1}.
        for ((u, v), vn) in self.u.iter_mut().zip(self.v.iter_mut()).zip(&self.rhs) {
            *u += dt * ((1.0 - th) * *v + th * vn);
            *v = *vn;
        }
        self.impulse = p;
        self.n += 1;
        (self.lams[0], self.acts[0]) = (-p / dt, active);
        crate::contact_step_report(self.n, self.time(), &self.dy.contacts, &self.u, None, &self.lams, &self.acts)
    }
}

// ---- The registry's row of this file: moreau-jean.

use crate::family::{check, Capabilities, Family, Group, Node, Param, Preset, SchemeSpec};

/// θ of the Moreau–Jean family and its projected variants.
pub(crate) const THETA: Param = Param { name: "theta", symbol: "θ", syntax: "THETA", allowed: "∈ [1/2, 1]", default: None };
/// Their restitution `e`.
pub(crate) const E: Param = Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: None };
/// The activation predictor's γ (default ½).
pub(crate) const GAMMA: Param = Param { name: "gamma", symbol: "γ", syntax: "GAMMA", allowed: "∈ [0, 1]", default: Some(0.5) };

/// The ranges of [`THETA`], [`E`] and, when the family takes it, [`GAMMA`]
/// (`a` holds one value per parameter of the family).
pub(crate) fn check_params(a: &[f64]) -> Result<(), SchemeError> {
    check("theta", a[0], (0.5..=1.0).contains(&a[0]), "[1/2, 1]")?;
    check("e", a[1], (0.0..=1.0).contains(&a[1]), "[0, 1]")?;
    a.get(2).map_or(Ok(()), |&g| check("gamma", g, (0.0..=1.0).contains(&g), "[0, 1]"))
}

/// Moreau–Jean (velocity-level θ-scheme, Newton's impact law), θ ∈ [1/2, 1], e ∈ [0, 1],
/// the activation predictor's γ ∈ [0, 1] (default 1/2).
pub(crate) static MOREAU_JEAN: Family = Family {
    name: "moreau-jean",
    about: "Moreau–Jean: velocity-level θ-scheme with Newton's impact law, activation predicted by u + γ dt v (docs/theory.md §4.6.4)",
    params: &[THETA, E, GAMMA],
    presets: &[Preset { name: "moreau-jean", args: &[0.5, 0.0, 0.5], group: Group::Peer, rank: 3 }],
    validate: check_params,
    capabilities: |_| Capabilities { node: Node::Massive, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(MoreauJean::new(s.to_string(), dy, s.args()[0], s.args()[1], s.args()[2], dt, init)?)),
};

impl SchemeSpec {
    /// Moreau–Jean with θ and restitution `e`, the predictor's γ = 1/2 (not validated until built).
    pub fn moreau_jean(theta: f64, restitution: f64) -> Self {
        MOREAU_JEAN.with(&[theta, restitution, 0.5])
    }

    /// Moreau–Jean with θ, restitution `e` and the activation predictor's
    /// γ (`u_c + γ dt v_c` reaching a bound; not validated until built).
    pub fn moreau_jean_gamma(theta: f64, restitution: f64, gamma: f64) -> Self {
        MOREAU_JEAN.with(&[theta, restitution, gamma])
    }
}
