//! Nitsche's method at the bar's contact node with the explicit Verlet
//! scheme (Chouly–Renard 2018, docs/theory.md §4.6.8).
//!
//! The semi-discrete problem is `nitsche`'s (§4.6.2): with `k = c²/h =
//! −K_01`, `d = k (e_1 − e_0)` (`σ(v) = dᵀv`), `γ = γ_0 k`, `θ ∈ [−1, 1]`,
//!
//! ```text
//! M U'' + K_N U + N(U) = F(t),   K_N = K − (θ/γ) d dᵀ,
//! N(U) = (1/γ) min(0, P_γ(U)) (θ d + γ e_0),   P_γ(U) = dᵀU + γ (u_0 − g),
//! ```
//!
//! and every term of the step is explicit (velocity Verlet, the central
//! difference `M (U^{n+1} − 2Uⁿ + U^{n−1}) = dt² (Fⁿ − K_N Uⁿ − N(Uⁿ))`):
//!
//! ```text
//! V^{n+½} = Vⁿ + (dt/2) Aⁿ,   U^{n+1} = Uⁿ + dt V^{n+½},
//! V^{n+1} = V^{n+½} + (dt/2) A^{n+1},   M Aⁿ = Fⁿ − K_N Uⁿ − N(Uⁿ).
//! ```
//!
//! One solve with `M` a step (a diagonal division with the lumped mass).
//! The reported force is `λ = min(0, P_γ(Uⁿ))` at `t_n`.
//!
//! Energy: with `E^{n+½} = ½ V^{n+½}ᵀ M V^{n+½} + ½ U^{n+1}ᵀ K_N Uⁿ`,
//! `E^{n+½} − E^{n−½} = (Fⁿ − N(Uⁿ))ᵀ (U^{n+1} − U^{n−1})/2` exactly (tested).
//!
//! Stability: the step is piecewise linear, with the pencil `(K_N, M)` off
//! contact and `(K_C, M)`, `K_C = K + θ d e_0ᵀ + e_0 dᵀ + γ e_0 e_0ᵀ`, in
//! contact. For θ = 1 `K_C` is symmetric (`K_N + q qᵀ/γ`, `q = d + γ e_0`);
//! for θ ≠ 1 it is not, and with a diagonal mass its pencil is block
//! triangular: node 0 alone, `(γ − θk + K_00 − k)/M_00`, and the bar held at
//! node 0, `(K, M)` without dof 0. The limit is `2/sqrt(κ)` of the larger
//! `κ_max` of the two phases (θ ≠ 1 needs the lumped mass).

use crate::nitsche::NitscheTerms;
use crate::onestep::{not_plain, with_avx2, Col, LumpedEnergy, LumpedTri};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::Active;
use signorini_fem::{BandLdlt, SymBand};

/// Nitsche + explicit Verlet on the P1 bar.
pub struct VerletNitsche {
    label: String,
    dt: f64,
    n: usize,
    dy: Dynamics,
    k_n: SymBand,
    m: BandLdlt,
    q: [f64; 2],
    r: [f64; 2],
    gamma_n: f64,
    u: Vec<f64>,
    v: Vec<f64>,
    /// `Aⁿ = M⁻¹ (Fⁿ − K_N Uⁿ − N(Uⁿ))`.
    acc: Vec<f64>,
    ku: Vec<f64>,
    /// `F(t_n)`.
    f: Vec<f64>,
    force: f64,
    lams: [f64; 1],
    acts: [Active; 1],
    /// A lumped mass: `K_N` and `M`'s inverse pivots for the step's fused
    /// end ([`end_pass`]).
    lumped: Option<LumpedTri>,
    /// With `lumped`: the energy's sums in one pass.
    mass_tri: Option<LumpedEnergy>,
}

/// The end of the step on a lumped mass in one vectorised pass: per row
/// `Aⁿ⁺¹ = M⁻¹ (F − K_N Uⁿ⁺¹ − N(Uⁿ⁺¹))` (the force's terms `n0`, `n1` on
/// rows 0 and 1; `M⁻¹` as `BandLdlt::solve_in_place`'s diagonal path,
/// checked by [`not_plain`]) into `acc` and `Vⁿ⁺¹ = V^{n+½} + dt/2 Aⁿ⁺¹`
/// into `v_new`, with the plain step's operations in their order. False
/// if some product is infinite, NaN or `−0` (`v` untouched).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn end_pass<C: Col>(lt: &LumpedTri, [ksl, kdc, ksr, dc]: [C; 4], u: &[f64], f: &[f64], v: &[f64], n0: f64, n1: f64, h: f64, acc: &mut [f64], v_new: &mut [f64]) -> bool {
    let n = u.len();
    let l = n - 1;
    let (f, v, acc, v_new, inv_d) = (&f[..n], &v[..n], &mut acc[..n], &mut v_new[..n], &lt.inv_d[..n]);
    let (kd, ks) = (&lt.kd[..n], &lt.ks[..n]);
    let (k0, kl) = lt.ku_ends(u);
    // Rows 0, 1 and n − 1 (row 1 may be the last).
    let k1 = if n > 2 { ks[1] * u[0] + kd[1] * u[1] + ks[2] * u[2] } else { kl };
    let a0 = (f[0] - k0 - n0) * inv_d[0];
    let a1 = (f[1] - k1 - n1) * inv_d[1];
    let al = (f[l] - kl) * inv_d[l];
    let mut odd = not_plain(a0) | not_plain(a1);
    (acc[0], acc[1]) = (a0, a1);
    (v_new[0], v_new[1]) = (v[0] + h * a0, v[1] + h * a1);
    if n > 2 {
        odd |= not_plain(al);
        acc[l] = al;
        v_new[l] = v[l] + h * al;
    }
    if n > 3 {
        // The coefficient columns (slices or `Same`): [`LumpedTri::columns`].
        let (_, [um, uc, up], _) = lt.interior(u);
        let (ksl, kdc, ksr, um, uc, up, dc) = (ksl.from(1), kdc.from(1), ksr.from(1), &um[1..], &uc[1..], &up[1..], dc.from(1));
        let (fc, vc, ac, vnc) = (&f[2..l], &v[2..l], &mut acc[2..l], &mut v_new[2..l]);
        for j in 0..n - 3 {
            let x = (fc[j] - (ksl.at(j) * um[j] + kdc.at(j) * uc[j] + ksr.at(j) * up[j])) * dc.at(j);
            odd |= not_plain(x);
            ac[j] = x;
            vnc[j] = vc[j] + h * x;
        }
    }
    odd == 0
}

/// The structure the scheme needs ([`crate::nitsche::bar_end`]) and a P1
/// bar's stiffness: returns `k = −K_01`.
fn bar_end(dy: &Dynamics) -> Result<f64, SchemeError> {
    crate::nitsche::bar_end(dy)?;
    let k = -dy.stiffness.get(0, 1);
    if !(k > 0.0 && k.is_finite()) {
        return Err(SchemeError::Structure("verlet-nitsche needs the P1 bar's stiffness (K_01 < 0)"));
    }
    Ok(k)
}

/// Whether the mass couples node 0 to no other (the lumped bar's).
fn node0_decoupled(m: &SymBand) -> bool {
    (1..m.n().min(m.half_bandwidth() + 1)).all(|j| m.get(0, j) == 0.0)
}

/// The exact critical step of the two phases (module docs).
fn critical_dt(gamma0: f64, theta: f64, dy: &Dynamics) -> Result<f64, SchemeError> {
    let k = bar_end(dy)?;
    let gamma = gamma0 * k;
    let free = crate::family::kappa_bound(&NitscheTerms::new(dy, gamma0, theta).k_n, &dy.mass)?;
    let contact = if theta == 1.0 {
        // K_C = K + d e_0ᵀ + e_0 dᵀ + γ e_0 e_0ᵀ: (0,0) += γ − 2k, (0,1) += k.
        let mut k_c = dy.stiffness.clone();
        k_c.add(0, 0, gamma - 2.0 * k);
        k_c.add(0, 1, k);
        crate::family::kappa_bound(&k_c, &dy.mass)?
    } else {
        if !node0_decoupled(&dy.mass) {
            return Err(SchemeError::Invalid { field: "theta", value: theta, allowed: "1 with a non-diagonal mass (θ ≠ 1 needs the lumped mass)" });
        }
        let node = (gamma - theta * k + dy.stiffness.get(0, 0) - k) / dy.mass.get(0, 0);
        node.max(crate::family::kappa_bound(&dy.stiffness.trailing(1), &dy.mass.trailing(1))?)
    };
    Ok(2.0 / free.max(contact).sqrt())
}

impl VerletNitsche {
    /// Sets up the scheme: Nitsche parameters `γ_0 > max(0, θ)`,
    /// `θ ∈ [−1, 1]`; the contact node must be dof 0, the end of one P1
    /// element, massive, with a one-sided obstacle; `dt` must be below the
    /// limit (module docs), which is not checked here (the registry does).
    pub fn new(label: String, dy: Dynamics, gamma0: f64, theta: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        if dy.damping.is_some() {
            return Err(crate::onestep::no_damping(&label));
        }
        if dy.k() > 1 {
            return Err(crate::family::not_taken(
                label,
                crate::family::Refused::SeveralContacts,
                " (Nitsche's method is formulated here at the bar's end node 0: its flux σ = c² u_x(0) is one element's)",
            ));
        }
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped)" });
        }
        if theta != 1.0 && !node0_decoupled(&dy.mass) {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "the lumped mass when θ ≠ 1 (the contact pencil is not symmetric)" });
        }
        crate::family::check("gamma0", gamma0, gamma0 > 0.0 && gamma0 > theta, "finite, > 0 and > θ")?;
        crate::family::check("theta", theta, (-1.0..=1.0).contains(&theta), "[-1, 1]")?;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
        }
        bar_end(&dy)?;
        let NitscheTerms { gamma_n, k_n, q, r } = NitscheTerms::new(&dy, gamma0, theta);
        let m = dy.mass.factor()?;
        // Its pass takes rows 2..n−1 from the columns (rows 0, 1 carry Nitsche's terms).
        let lumped = LumpedTri::uniform_from(&m, &k_n, 2);
        let n = dy.n();
        let mut s = Self {
            label,
            dt,
            n: 0,
            k_n,
            m,
            q,
            r,
            gamma_n,
            u: init.u.clone(),
            v: init.v.clone(),
            acc: vec![0.0; n],
            ku: vec![0.0; n],
            f: vec![0.0; n],
            force: 0.0,
            lams: [0.0],
            acts: [Active::None],
            mass_tri: lumped.as_ref().and_then(|lt| LumpedEnergy::new(&dy.mass, lt)),
            lumped,
            dy,
        };
        s.update_acc();
        s.report();
        Ok(s)
    }

    /// `Aⁿ = M⁻¹ (F(t_n) − K_N Uⁿ − N(Uⁿ))` and the force `min(0, P_γ(Uⁿ))`.
    fn update_acc(&mut self) {
        let t = self.n as f64 * self.dt;
        self.dy.load_at(t, &mut self.f);
        self.k_n.mul_vec(&self.u, &mut self.ku);
        for ((a, f), k) in self.acc.iter_mut().zip(&self.f).zip(&self.ku) {
            *a = f - k;
        }
        let p = self.q[0] * self.u[0] + self.q[1] * self.u[1] - self.gamma_n * self.dy.contact().bounds.lo;
        self.force = p.min(0.0);
        self.acc[0] -= self.force * self.r[0];
        self.acc[1] -= self.force * self.r[1];
        self.m.solve_in_place(&mut self.acc);
    }

    /// [`update_acc`](Self::update_acc) and the half kick `V += dt/2 A` in
    /// one pass on a lumped mass ([`end_pass`]; `Vⁿ⁺¹` made in `ku`, then
    /// swapped in). False, `V` untouched, without a lumped mass or where the
    /// pass gives up.
    fn fused_end(&mut self, h: f64) -> bool {
        let Some(lt) = &self.lumped else { return false };
        if !self.dy.forcing.is_empty() {
            self.dy.load_at(self.n as f64 * self.dt, &mut self.f);
        }
        // (Without forcing `f` holds the steady load since `new`.)
        let p = self.q[0] * self.u[0] + self.q[1] * self.u[1] - self.gamma_n * self.dy.contact().bounds.lo;
        let force = p.min(0.0);
        let (n0, n1) = (force * self.r[0], force * self.r[1]);
        let (u, f, v, acc, v_new) = (&self.u[..], &self.f[..], &self.v[..], &mut self.acc[..], &mut self.ku[..]);
        let done = with_avx2!(lt.avx2, fn(lt: &LumpedTri, u: &[f64], f: &[f64], v: &[f64], n0: f64, n1: f64, h: f64, acc: &mut [f64], v_new: &mut [f64]) -> bool {
            // A uniform mesh's coefficients as scalars (the same values: the same bits).
            match lt.uniform {
                Some(c) => end_pass(lt, c, u, f, v, n0, n1, h, acc, v_new),
                None => end_pass(lt, lt.columns(u.len()), u, f, v, n0, n1, h, acc, v_new),
            }
        });
        if done {
            self.force = force;
            std::mem::swap(&mut self.v, &mut self.ku);
        }
        done
    }

    fn report(&mut self) {
        let active = if self.force < 0.0 { Active::Lower } else { Active::None };
        (self.lams[0], self.acts[0]) = (self.force, active);
    }

    /// The Nitsche force vector `N(Uⁿ)` (entries 0 and 1; zero elsewhere).
    pub fn force_vector(&self) -> [f64; 2] {
        [self.force * self.r[0], self.force * self.r[1]]
    }

    /// Velocity `Vⁿ`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }
}

impl Stepper for VerletNitsche {
    stepper_accessors!();

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let h = 0.5 * self.dt;
        for ((u, v), a) in self.u.iter_mut().zip(self.v.iter_mut()).zip(&self.acc) {
            *v += h * a;
            *u += self.dt * *v;
        }
        self.n += 1;
        if !self.fused_end(h) {
            self.update_acc();
            for (v, a) in self.v.iter_mut().zip(&self.acc) {
                *v += h * a;
            }
        }
        let t = self.time();
        if !(self.u[0].is_finite() && self.force.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        self.report();
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.force)), active: self.acts[0] })
    }

    /// `½ VⁿᵀM Vⁿ + ½ UⁿᵀK_N Uⁿ − F(t_n)ᵀUⁿ` at `t_n`.
    fn energy(&mut self) -> Option<(f64, f64)> {
        let (kin, pot, load) = if let (Some(lt), Some(me)) = (&self.lumped, &self.mass_tri) {
            // The three sums in one pass, the same bits (`lt` holds `K_N`'s diagonals).
            me.sums(lt, &self.v, &self.u, None, &self.f, 1.0)
        } else {
            let kin = self.dy.mass.quad_form(&self.v);
            let pot = self.k_n.quad_form(&self.u);
            let load: f64 = self.f.iter().zip(&self.u).map(|(f, u)| f * u).sum();
            (kin, pot, load)
        };
        Some((self.time(), 0.5 * kin + 0.5 * pot - load))
    }
}

// ---- The registry's row of this file: verlet-nitsche.

use crate::family::{check, Capabilities, Family, Node, Param, SchemeSpec};

/// Nitsche's method with the explicit Verlet scheme: γ = γ_0 c²/h
/// (γ_0 > max(0, θ)), θ ∈ [-1, 1]; θ ≠ 1 needs the lumped mass.
pub(crate) static VERLET_NITSCHE: Family = Family {
    name: "verlet-nitsche",
    about: "Nitsche's method with the explicit Verlet scheme at the bar's end node (Chouly–Renard; docs/theory.md §4.6.8)",
    params: &[
        Param { name: "gamma0", symbol: "γ_0", syntax: "GAMMA0", allowed: "> max(0, θ)", default: None },
        Param { name: "theta", symbol: "θ", syntax: "THETA", allowed: "∈ [-1, 1] (θ ≠ 1: lumped mass)", default: None },
    ],
    presets: &[],
    validate: |a| {
        check("theta", a[1], (-1.0..=1.0).contains(&a[1]), "[-1, 1]")?;
        check("gamma0", a[0], a[0] > 0.0 && a[0] > a[1], "finite, > 0 and > θ")
    },
    capabilities: |a| Capabilities {
        explicit: true,
        node: Node::Massive,
        // θ = 1 takes either massive-node mass, θ ≠ 1 the lumped one only; a
        // θ not given (NaN: `signorini list` reads a family at its defaults,
        // and θ has none) needs no diagonal mass: the range line says θ ≠ 1's.
        diagonal_mass: a[1] != 1.0 && !a[1].is_nan(),
        damping: false,
        forcing: true,
        restitution: false,
        stiffness: false,
        several_contacts: false,
        beam: false,
        lockstep: false,
    },
    cfl_limit: |a, dy| critical_dt(a[0], a[1], dy).map(Some),
    stability_rule: |a| {
        Some(if a[1] == 1.0 {
            "explicit Verlet with Nitsche's term: 2/sqrt(κ_max) of the larger of the pencils (K_N, M) off contact and (K_N + q qᵀ/γ, M) in contact"
        } else {
            "explicit Verlet with Nitsche's term (lumped mass): 2/sqrt(κ_max) of the larger of (K_N, M) off contact and, in contact, node 0 alone ((γ − θk + K_00 − k)/M_00) or the bar held at node 0"
        })
    },
    build: |s, dy, dt, init| {
        let st = VerletNitsche::new(s.to_string(), dy, s.args()[0], s.args()[1], dt, init)?;
        s.check_cfl(&st.dy, dt, false)?;
        Ok(Box::new(st))
    },
};

impl SchemeSpec {
    /// Nitsche's method with the explicit Verlet scheme, γ_0 and θ (not
    /// validated until built).
    pub fn verlet_nitsche(gamma0: f64, theta: f64) -> Self {
        VERLET_NITSCHE.with(&[gamma0, theta])
    }
}
