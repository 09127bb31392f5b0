//! Schemes on the reduced formulation of a massless contact node (docs/theory.md §4.5,
//! weighted-mass paper §3 and §5).
//!
//! With row/column 0 of `M` zero, node 0 is in quasi-static equilibrium
//! `(K U)_0 = F_0 - λ`, `u_0 >= g`, `λ <= 0`, complementary, so
//! `u_0 = max(u_1 + a, g)` with `a = F_0/k` and `k = c²/h = -K_01`. The
//! unknowns `U = (u_1, …)` then obey the ODE with Lipschitz right-hand side
//!
//! ```text
//! M* U'' + K* U = F* + k g e_1 + k (w)⁺ e_1,    w = u_1 - ĝ,  ĝ = g - a,
//! ```
//!
//! (`M*`, `K*`: `M`, `K` without node 0; `F* = F[1..]`). For `g = 0`, `F_0 = 0`,
//! `c = 1` this is the paper's `M* U'' + S* U = F + (1/h) u_1⁺ e_1`.
//!
//! Both schemes here are the trapezoidal/midpoint family
//! `U^{n+1} = U^n + dt/2 (V^n + V^{n+1})`,
//! `M* (V^{n+1} - V^n)/dt + K* (U^n + U^{n+1})/2 = F* + k g e_1 + N e_1`,
//! i.e. `(M* + dt²/4 K*) U^{n+1} = M*(U^n + dt V^n) - dt²/4 K* U^n + dt²/2 (F_eff + N e_1)`,
//! and differ only in the contact term `N`, a piecewise-linear function of
//! `w^{n+1}` for a given `w^n` — so each step is one solve plus the exact
//! branch-by-branch scalar solve of [`signorini_contact::solve_piecewise_linear`]:
//!
//! In floating point the term is split as `y⁺ = y + (-y)⁺`: the linear part
//! `k w` joins the matrix (`K' = K* - k e_1e_1ᵀ`, the stiffness seen when the
//! node follows node 1) and the load (`F' = F* + F_0 e_1`), and only the
//! contact part `k (-w)⁺`-type term stays in `N` — so a distant obstacle
//! never brings large numbers into the arithmetic.
//!
//! * [`ReducedLaw::Hybrid`] (paper §5): `N = H(-wⁿ) k/2 (wⁿ + wⁿ⁺¹)⁺ + H(wⁿ) k/2 ((wⁿ)⁺ + (wⁿ⁺¹)⁺)`
//!   (midpoint while the node is in contact, Crank–Nicolson while it is free;
//!   `H(0) = 1/2`, where both branches coincide). Its energy
//!   `E = ½ VᵀM*V + ½ UᵀK*U - F_effᵀU - k/2 ((w)⁺)²` never increases
//!   (Lemma 5.1), and is conserved while the node stays free.
//! * [`ReducedLaw::CrankNicolson`] (paper Lemma 3.1, eq. (3.6)): `N = k/2 ((wⁿ)⁺ + (wⁿ⁺¹)⁺)`,
//!   the trapezoidal rule on the reduced ODE. It is `newmark-cn` with a
//!   massless node, except at the first step, where Newmark uses the initial
//!   `u_0` as given and the reduced scheme the equilibrated one (tested).
//!
//! The reported displacement has all dofs, with `u_0 = max(u_1 + a, g)`; the
//! contact force is `λ = k min(w, 0)` at `t_{n+1}`; the energy is the
//! physical one, `½ V*ᵀM*V* + ½ UᵀKU - FᵀU` on the full vector (equal to `E`
//! above up to a constant).

use crate::fused::{fused_switches, FusedSwitch};
use crate::stabilized::{neighbours, tridiagonal_forward_dispatch, TriRows};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{solve_piecewise_linear, Active, PiecewiseLinear};
use signorini_fem::{BandLdlt, SymBand};

/// The contact term of a reduced scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReducedLaw {
    /// The hybrid Crank–Nicolson/midpoint law (energy non-increasing).
    Hybrid,
    /// Crank–Nicolson on the reduced ODE (the paper's Lemma 3.1 scheme).
    CrankNicolson,
    /// The explicit central difference (Newmark β = 0, γ = 1/2) on the
    /// reduced ODE: the contact node is quasi-static (`u_0 = max(u_1 + a, g)`
    /// at every step, as in GetFEM's demo), the rest explicit with `M*`;
    /// conditionally stable, dt < 2/sqrt(κ_max(K*, M*)).
    CentralDifference,
}

/// A scheme on the reduced formulation of a massless contact node.
pub struct Reduced {
    label: String,
    law: ReducedLaw,
    dt: f64,
    n: usize,
    dy: Dynamics,
    m_star: SymBand,
    a: BandLdlt,
    /// `K' = K* - k e_1 e_1ᵀ`.
    k_free: SymBand,
    /// `A⁻¹ e_1` with `A = M* + dt²/4 K'` (reduced numbering: index 0 is node 1).
    w: Vec<f64>,
    /// `F' = F* + F_0 e_1`.
    f_eff: Vec<f64>,
    k: f64,
    g_hat: f64,
    a_shift: f64,
    u: Vec<f64>,
    v: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    lambda: f64,
    /// `A^n` (reduced), for the explicit central difference.
    acc: Vec<f64>,
    lams: [f64; 1],
    acts: [Active; 1],
    /// The implicit step fused on the P1 bar ([`Tridiagonal`]), if it applies, and its switches.
    fused: FusedSwitch<Tridiagonal>,
}

/// The implicit step fused on the P1 bar (`M*`, `K'` and the factor of `A`
/// tridiagonal, `L` not the identity): the right-hand side
/// `M*(U + dt V) − dt²/4 K' U + dt²/2 F'` made row by row inside the
/// forward sweep of the solve (the shared
/// [`tridiagonal_forward`](crate::stabilized::tridiagonal_forward), as
/// `contact-stabilized`'s), `U + dt V` computed where a row needs it
/// instead of in a pass of its own, then the factor's backward sweep. Every
/// value is the general path's operations in the same order (its pass,
/// `SymBand::mul_vec`'s tridiagonal rows, the sum,
/// `BandLdlt::solve_in_place`'s sweeps), so the same bits (cost:
/// `crates/run/benches/step.rs`, `massless_node_scheme_step`).
type Tridiagonal = crate::stabilized::TriPair;

/// [`Tridiagonal`]'s rows for one step: `M* (u + dt v) + (−q K' u + 2q f)`.
struct ReducedRows<'a> {
    t: &'a Tridiagonal,
    dt: f64,
    q: f64,
    u: &'a [f64],
    v: &'a [f64],
    f: &'a [f64],
}

impl TriRows for ReducedRows<'_> {
    #[inline(always)]
    fn interior(&self, a: usize, o: &mut [f64]) {
        let len = o.len();
        let (u, v, dt, q) = (self.u, self.v, self.dt, self.q);
        let (ul, uc, ur) = neighbours(u, a, len);
        let (vl, vc, vr) = neighbours(v, a, len);
        let (msl, mdc, msr) = self.t.m.window(a, len);
        let (ksl, kdc, ksr) = self.t.k.window(a, len);
        let fr = &self.f[a..a + len];
        for j in 0..len {
            let mt = msl[j] * (ul[j] + dt * vl[j]) + mdc[j] * (uc[j] + dt * vc[j]) + msr[j] * (ur[j] + dt * vr[j]);
            let ku = ksl[j] * ul[j] + kdc[j] * uc[j] + ksr[j] * ur[j];
            o[j] = mt + (-q * ku + 2.0 * q * fr[j]);
        }
    }

    #[inline(always)]
    fn edge(&self, i: usize) -> f64 {
        let (u, v, n) = (self.u, self.v, self.u.len());
        let mt = self.t.m.row(n, i, |j| u[j] + self.dt * v[j]);
        let ku = self.t.k.row(n, i, |j| u[j]);
        mt + (-self.q * ku + 2.0 * self.q * self.f[i])
    }
}

impl Reduced {
    /// Sets up the scheme; the problem must have a massless contact node at
    /// dof 0 that belongs to one element (`K_00 = -K_01`) and a one-sided
    /// obstacle.
    pub fn new(label: String, dy: Dynamics, law: ReducedLaw, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        if dy.damping.is_some() {
            return Err(crate::onestep::no_damping(&label));
        }
        let n = dy.n();
        if dy.k() > 1 {
            return Err(crate::family::not_taken(label, crate::family::Refused::SeveralContacts, " (the reduced schemes eliminate one massless contact node at dof 0)"));
        }
        if !dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massless contact node (mass mod, mod1, mod2, mod3, transfer or singular)" });
        }
        if dy.contact().bounds.hi.is_finite() {
            return Err(SchemeError::Structure("the reduced schemes handle a one-sided obstacle only"));
        }
        if n < 2 {
            return Err(SchemeError::Structure("the reduced schemes need at least two unknowns"));
        }
        let k = -dy.stiffness.get(0, 1);
        if !(k > 0.0) || (dy.stiffness.get(0, 0) - k).abs() > 1e-12 * k || dy.stiffness.half_bandwidth() != 1 {
            return Err(SchemeError::Structure("the contact node must be the end node of one P1 element"));
        }
        for (what, v) in [("initial displacement", &init.u), ("initial velocity", &init.v)] {
            if v.len() != n {
                return Err(SchemeError::Size { what, got: v.len(), expected: n });
            }
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
        }
        let m_star = dy.mass.trailing(1);
        // K' = K* - k e_1 e_1ᵀ, K* the stiffness without node 0.
        let mut k_free = dy.stiffness.trailing(1);
        k_free.add(0, 0, -k);
        let explicit = law == ReducedLaw::CentralDifference;
        let a = m_star.lin_comb(1.0, &k_free, if explicit { 0.0 } else { dt * dt / 4.0 }).factor()?;
        let mut w = vec![0.0; n - 1];
        w[0] = 1.0;
        a.solve_in_place(&mut w);
        let fused = FusedSwitch::new(if explicit { None } else { Tridiagonal::beside(&m_star, &k_free, &a) });
        let g = dy.contact().bounds.lo;
        let a_shift = dy.load[0] / k;
        let mut f_eff = dy.load[1..].to_vec();
        f_eff[0] += dy.load[0];
        let mut s = Self {
            label,
            law,
            dt,
            n: 0,
            m_star,
            k_free,
            a,
            w,
            f_eff,
            k,
            g_hat: g - a_shift,
            a_shift,
            u: init.u.clone(),
            v: init.v[1..].to_vec(),
            rhs: vec![0.0; n - 1],
            tmp: vec![0.0; n - 1],
            lambda: 0.0,
            acc: vec![0.0; n - 1],
            lams: [0.0],
            acts: [Active::None],
            fused,
            dy,
        };
        s.equilibrate();
        if explicit {
            s.update_acceleration();
        }
        Ok(s)
    }

    /// `u_0 = max(u_1 + a, g)` and the force that holds it.
    fn equilibrate(&mut self) -> f64 {
        let w = self.u[1] - self.g_hat;
        self.u[0] = (self.u[1] + self.a_shift).max(self.dy.contact().bounds.lo);
        self.lambda = self.k * w.min(0.0);
        w
    }

    /// `A = M*⁻¹ (F' - K'U + k (-w)⁺ e_1)` (explicit central difference).
    fn update_acceleration(&mut self) {
        let w = self.u[1] - self.g_hat;
        self.k_free.mul_vec(&self.u[1..], &mut self.acc);
        for (a, f) in self.acc.iter_mut().zip(&self.f_eff) {
            *a = f - *a;
        }
        self.acc[0] += self.k * (-w).max(0.0);
        self.a.solve_in_place(&mut self.acc);
    }

    fn step_central_difference(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
        // U^{n+1} = U^n + dt V^n + dt²/2 A^n; V^{n+1} = V^n + dt/2 (A^n + A^{n+1}).
        for ((u, v), a) in self.u[1..].iter_mut().zip(&mut self.v).zip(&self.acc) {
            *u += dt * *v + 0.5 * dt * dt * a;
            *v += 0.5 * dt * a;
        }
        let w_new = self.equilibrate();
        self.update_acceleration();
        for (v, a) in self.v.iter_mut().zip(&self.acc) {
            *v += 0.5 * dt * a;
        }
        self.n += 1;
        let t = self.time();
        if !(self.u[1].is_finite() && self.lambda.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.lambda)), active: if w_new < 0.0 { Active::Lower } else { Active::None } })
    }

    /// `K' = K* - k e_1 e_1ᵀ` (stiffness with the contact node following node 1).
    pub fn free_stiffness(&self) -> &SymBand {
        &self.k_free
    }

    /// `M*` (the mass matrix without node 0).
    pub fn reduced_mass(&self) -> &SymBand {
        &self.m_star
    }

    /// The current contact force `λ = k min(w, 0)`.
    pub fn lambda_now(&self) -> f64 {
        self.lambda
    }

    /// `F' = F* + F_0 e_1`.
    pub fn reduced_load(&self) -> &[f64] {
        &self.f_eff
    }

    /// The contact part `N'(x)` of the law, `x = w^{n+1}`, given `w^n`
    /// (non-increasing in `x`; zero while the node stays free):
    /// hybrid `k/2 (-x)⁺` if `wⁿ >= 0`, `k/2 (-wⁿ - x)⁺` if `wⁿ < 0`;
    /// Crank–Nicolson `k/2 ((-wⁿ)⁺ + (-x)⁺)`.
    fn law(&self, wn: f64) -> ([f64; 1], [(f64, f64); 2]) {
        let h2 = 0.5 * self.k;
        match self.law {
            ReducedLaw::Hybrid if wn < 0.0 => ([-wn], [(-h2 * wn, -h2), (0.0, 0.0)]),
            ReducedLaw::Hybrid => ([0.0], [(0.0, -h2), (0.0, 0.0)]),
            ReducedLaw::CrankNicolson => {
                let c = h2 * (-wn).max(0.0);
                ([0.0], [(c, -h2), (c, 0.0)])
            }
            // Not used: the explicit scheme needs no scalar solve.
            ReducedLaw::CentralDifference => ([0.0], [(0.0, 0.0), (0.0, 0.0)]),
        }
    }

    /// Reduced velocity `V*` (nodes 1..).
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// The contact law in use.
    pub fn reduced_law(&self) -> ReducedLaw {
        self.law
    }

    /// The paper's energy `½ VᵀM*V + ½ UᵀK*U - Fᵀ U - k/2 (w⁺)²` up to a
    /// constant, evaluated in the split form
    /// `½ VᵀM*V + ½ UᵀK'U - F'ᵀU + k/2 ((-w)⁺)²` (equal to the physical
    /// energy up to a constant).
    pub fn reduced_energy(&self) -> f64 {
        let us = &self.u[1..];
        let wm = (self.g_hat - self.u[1]).max(0.0);
        let f: f64 = self.f_eff.iter().zip(us).map(|(f, u)| f * u).sum();
        0.5 * self.m_star.quad_form(&self.v) + 0.5 * self.k_free.quad_form(us) - f + 0.5 * self.k * wm * wm
    }
}

impl Stepper for Reduced {
    stepper_accessors!();

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let r = if self.law == ReducedLaw::CentralDifference { self.step_central_difference()? } else { self.step_implicit()? };
        self.lams[0] = self.lambda;
        self.acts[0] = r.active;
        Ok(r)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        let kin = self.m_star.quad_form(&self.v);
        let pot = self.dy.stiffness.quad_form(&self.u);
        let load: f64 = self.dy.load.iter().zip(&self.u).map(|(f, u)| f * u).sum();
        Some((self.time(), 0.5 * kin + 0.5 * pot - load))
    }
}

impl Reduced {
    fused_switches!(fused);

    fn step_implicit(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
        let q = dt * dt / 4.0;
        let wn = self.u[1] - self.g_hat;
        // rhs = M*(U + dt V) - dt²/4 K* U + dt²/2 F_eff
        if let Some(tri) = self.fused.active() {
            // The same right-hand side and solve, fused ([`Tridiagonal`]).
            let rows = ReducedRows { t: tri, dt, q, u: &self.u[1..], v: &self.v, f: &self.f_eff };
            let (l, _) = self.a.tridiagonal_factors().expect("tridiagonal");
            tridiagonal_forward_dispatch(tri.avx2, &rows, &[], &[], &[], l, &mut self.rhs);
            self.a.backward_in_place(&mut self.rhs);
        } else {
            let us = &self.u[1..];
            for ((t, u), v) in self.tmp.iter_mut().zip(us).zip(&self.v) {
                *t = u + dt * v;
            }
            self.m_star.mul_vec(&self.tmp, &mut self.rhs);
            self.k_free.mul_vec(us, &mut self.tmp);
            for ((b, ku), f) in self.rhs.iter_mut().zip(&self.tmp).zip(&self.f_eff) {
                *b += -q * ku + 2.0 * q * f;
            }
            self.a.solve_in_place(&mut self.rhs);
        }
        // u_1^{n+1} = y_1 + (dt²/2) w_1 N  →  x = (y_1 - ĝ) + W N(x).
        let big_w = 2.0 * q * self.w[0];
        let (breaks, branches) = self.law(wn);
        let (x, nval) = solve_piecewise_linear(self.rhs[0] - self.g_hat, big_w, PiecewiseLinear { breaks: &breaks, branches: &branches })?;
        if nval != 0.0 {
            // Contact part active: U^{n+1} = y + (dt²/2) N' A⁻¹e_1, with u_1 exact.
            let coef = 2.0 * q * nval;
            for (y, wi) in self.rhs.iter_mut().zip(&self.w) {
                *y += coef * wi;
            }
            self.rhs[0] = x + self.g_hat;
        }
        // V^{n+1} = 2 (U^{n+1} - U^n)/dt - V^n; U^{n+1}.
        for ((v, un), u1) in self.v.iter_mut().zip(self.u[1..].iter_mut()).zip(&self.rhs) {
            *v = 2.0 * (u1 - *un) / dt - *v;
            *un = *u1;
        }
        let w_new = self.equilibrate();
        self.n += 1;
        let t = self.time();
        if !(self.u[1].is_finite() && self.lambda.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.lambda)), active: if w_new < 0.0 { Active::Lower } else { Active::None } })
    }
}

// ---- The registry's rows of this file: hybrid, reduced-cn, cd-massless.

use crate::family::{kappa_bound, Capabilities, Family, Group, Node, Preset, SchemeSpec};

/// The reduced formulations' capabilities: a massless contact node at dof
/// 0, one contact, a steady load, no damping.
const REDUCED_CAPS: Capabilities = Capabilities {
    explicit: false,
    node: Node::Massless,
    diagonal_mass: false,
    damping: false,
    forcing: false,
    restitution: false,
    stiffness: false,
    several_contacts: false,
    beam: false,
    lockstep: false,
};

fn build_reduced(s: &SchemeSpec, dy: Dynamics, dt: f64, init: &Initial, law: ReducedLaw) -> Result<Box<dyn Stepper>, SchemeError> {
    if law == ReducedLaw::CentralDifference {
        s.check_cfl(&dy, dt, false)?;
    }
    Ok(Box::new(Reduced::new(s.to_string(), dy, law, dt, init)?))
}

/// The paper's hybrid scheme on the reduced formulation (§5).
pub(crate) static HYBRID: Family = Family {
    name: "hybrid",
    about: "hybrid CN/midpoint scheme on the reduced formulation (massless contact node; docs/theory.md §4.4)",
    params: &[],
    presets: &[Preset { name: "hybrid", args: &[], group: Group::Reduced, rank: 0 }],
    validate: |_| Ok(()),
    capabilities: |_| REDUCED_CAPS,
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| build_reduced(s, dy, dt, init, ReducedLaw::Hybrid),
};

/// Crank–Nicolson on the reduced ODE (Lemma 3.1).
pub(crate) static REDUCED_CN: Family = Family {
    name: "reduced-cn",
    about: "Crank–Nicolson on the reduced ODE (massless contact node; docs/theory.md §4.4)",
    params: &[],
    presets: &[Preset { name: "reduced-cn", args: &[], group: Group::Reduced, rank: 1 }],
    validate: |_| Ok(()),
    capabilities: |_| REDUCED_CAPS,
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| build_reduced(s, dy, dt, init, ReducedLaw::CrankNicolson),
};

/// The explicit central difference with a quasi-static massless node.
pub(crate) static CD_MASSLESS: Family = Family {
    name: "cd-massless",
    about: "explicit central difference with a quasi-static massless contact node (docs/theory.md §4.6)",
    params: &[],
    presets: &[Preset { name: "cd-massless", args: &[], group: Group::Peer, rank: 4 }],
    validate: |_| Ok(()),
    capabilities: |_| Capabilities { explicit: true, ..REDUCED_CAPS },
    cfl_limit: |_, dy| {
        if dy.massless_contact() && dy.contact().dof == 0 && dy.k() == 1 {
            // The reduced pencil (K*, M*): in contact the node is fixed and
            // node 1 feels the whole first element.
            let (k, m) = (dy.stiffness.trailing(1), dy.mass.trailing(1));
            Ok(Some(2.0 / kappa_bound(&k, &m)?.sqrt()))
        } else {
            Ok(None)
        }
    },
    stability_rule: |_| Some("explicit central difference with a quasi-static massless node: 2/sqrt(κ_max) of the reduced pencil (K*, M*) without the contact node"),
    build: |s, dy, dt, init| build_reduced(s, dy, dt, init, ReducedLaw::CentralDifference),
};

impl SchemeSpec {
    /// A scheme on the reduced formulation.
    pub fn reduced(law: ReducedLaw) -> Self {
        match law {
            ReducedLaw::Hybrid => HYBRID.with(&[]),
            ReducedLaw::CrankNicolson => REDUCED_CN.with(&[]),
            ReducedLaw::CentralDifference => CD_MASSLESS.with(&[]),
        }
    }
}
