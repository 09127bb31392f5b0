//! Massless contact dofs (docs/theory.md §9.3): the contact node of a mass
//! redistribution (`mod…`, `transfer`, `singular`) or of a reduced model
//! has no inertia, so its equation is static,
//!
//! ```text
//! K_ZZ q_Z + K_ZR q_R = f_Z(t) + r,   lo <= q_c <= hi,   r ⟂ bounds,
//! ```
//!
//! (`Z` the massless dofs, `R` the massive ones). A massless contact is
//! *free* (not held) while its condensed position
//! `q_S = K_SS⁻¹ (f_S − K_SR q_R − K_SA q_A)` stays inside its bounds, and
//! *held* at its bound while its static force `r_c = (K q − f)_c` presses.
//! In every phase the massive dofs follow a linear flow: the pencil on `R`
//! with the Schur complement `K_RR − K_RS K_SS⁻¹ K_SR` and the load
//! `f_R − K_RA q_A − K_RS K_SS⁻¹ (f_S − K_SA q_A)`. The events are a free
//! contact's condensed position reaching its bound (it *lands*: no velocity
//! of a massive dof jumps, no impulse; logged as an `impact` with velocity
//! after 0 and impulse 0) and a held contact's force reaching 0 (a
//! `release`). Both are functionals of the modal state, located by the same
//! search. Which contacts are held after an event is the static LCP on
//! `K_ZZ⁻¹` (the positions), then, for those at a bound without force, the
//! same LCP on the rates: a contact is held unless it leaves its bound.
//! There are no impacts, so no restitution acts (refused above 0) and the
//! energy `½ vᵀ M v + ½ qᵀ K q − fᵀ q` is conserved under a steady load.

use super::{EventDriven, Hold, Site, System, Work};
use crate::events::flow::{dense, Basis, Loads, ModalFlow, Piece};
use crate::events::record::{EventKind, EventRecord, EventsError};
use crate::events::Bound;
use crate::Dynamics;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use signorini_contact::MultiProjection;

/// The inverse of the SPD `a` (`None` if it is not positive definite).
fn spd_inverse(a: &Mat<f64>) -> Option<Mat<f64>> {
    let n = a.nrows();
    if n == 0 {
        return Some(Mat::zeros(0, 0));
    }
    let llt = a.llt(Side::Lower).ok()?;
    let mut x = Mat::<f64>::identity(n, n);
    llt.solve_in_place(x.as_mut());
    Some(x)
}

fn not_spd() -> EventsError {
    EventsError::Contacts("the stiffness block K_ZZ of the massless dofs is not positive definite (a massless dof without stiffness has no static position)".to_string())
}

/// The static condensation of a structure's massless dofs (module docs):
/// the dofs `fixed` held at their values, the `condensed` ones (massless,
/// not held) eliminated by their static equation `K_SS q_S = y_S − K_Sf
/// q_f` with `y = f − K_·h b_h` (`b_h` the fixed values), and the others,
/// the free dofs, left with
///
/// ```text
/// M_ff q_f'' + C_ff q_f' + K_eff q_f = y_f − K_fS K_SS⁻¹ y_S,   K_eff = K_ff − K_fS K_SS⁻¹ K_Sf
/// ```
///
/// (`K_eff` symmetrised: `½ (K_eff + K_effᵀ)`). The event-driven run's
/// phases with massless contacts and the orbits' parameter sensitivity are
/// built on it; the condensed dofs are recovered as `K_SS⁻¹ (f_S − K_S· q)`
/// ([`inverse`](Self::inverse), the other dofs' entries of `q`).
#[derive(Clone, Debug)]
pub struct Condensation {
    free: Vec<usize>,
    cond: Vec<usize>,
    fixed: Vec<(usize, f64)>,
    /// `K_SS⁻¹`.
    g: Mat<f64>,
    /// `K_fS K_SS⁻¹`.
    kfs_g: Mat<f64>,
    keff: Mat<f64>,
}

impl Condensation {
    /// The condensation of `dy`'s stiffness with the dofs `fixed` at their
    /// values and the dofs `condensed` (in that order) eliminated; an
    /// error if `K_SS` is not positive definite.
    ///
    /// # Panics
    /// If a dof is out of range or both fixed and condensed (a programmer
    /// error).
    #[track_caller]
    pub fn new(dy: &Dynamics, fixed: &[(usize, f64)], condensed: &[usize]) -> Result<Self, EventsError> {
        let n = dy.n();
        assert!(fixed.iter().map(|f| f.0).chain(condensed.iter().copied()).all(|d| d < n), "fixed and condensed dofs below {n}");
        assert!(condensed.iter().all(|d| !fixed.iter().any(|f| f.0 == *d)), "a dof both fixed and condensed");
        Self::of(&dense(&dy.stiffness), fixed.to_vec(), condensed.to_vec())
    }

    /// [`new`](Self::new) on the dense stiffness `k`.
    fn of(k: &Mat<f64>, fixed: Vec<(usize, f64)>, cond: Vec<usize>) -> Result<Self, EventsError> {
        let free: Vec<usize> = (0..k.nrows()).filter(|d| !cond.contains(d) && !fixed.iter().any(|f| f.0 == *d)).collect();
        let (nf, ns) = (free.len(), cond.len());
        let g = spd_inverse(&Mat::from_fn(ns, ns, |i, j| k[(cond[i], cond[j])])).ok_or_else(not_spd)?;
        let kfs_g = Mat::from_fn(nf, ns, |r, j| (0..ns).map(|s| k[(free[r], cond[s])] * g[(s, j)]).sum::<f64>());
        let keff = Mat::from_fn(nf, nf, |r, c| k[(free[r], free[c])] - (0..ns).map(|j| kfs_g[(r, j)] * k[(cond[j], free[c])]).sum::<f64>());
        let keff = Mat::from_fn(nf, nf, |r, c| 0.5 * (keff[(r, c)] + keff[(c, r)]));
        Ok(Self { free, cond, fixed, g, kfs_g, keff })
    }

    /// The free dofs, in order (the condensed system's rows).
    pub fn free(&self) -> &[usize] {
        &self.free
    }

    /// The condensed dofs, in the order given (`K_SS⁻¹`'s rows).
    pub fn condensed(&self) -> &[usize] {
        &self.cond
    }

    /// `K_eff`, on the free dofs.
    pub fn stiffness(&self) -> &Mat<f64> {
        &self.keff
    }

    /// `K_SS⁻¹`, on the condensed dofs.
    pub fn inverse(&self) -> &Mat<f64> {
        &self.g
    }

    /// The load map: `y_f − K_fS K_SS⁻¹ y_S` of `y` (every dof's entry).
    ///
    /// # Panics
    /// If `y` has fewer entries than the structure (a programmer error).
    pub fn load(&self, y: &[f64]) -> Vec<f64> {
        let ns = self.cond.len();
        (0..self.free.len()).map(|r| y[self.free[r]] - (0..ns).map(|j| self.kfs_g[(r, j)] * y[self.cond[j]]).sum::<f64>()).collect()
    }

    /// The free dofs' basis: `(M_ff, K_eff, C_ff)` of the dense `m`, `c`.
    fn basis(&self, m: &Mat<f64>, c: Option<&Mat<f64>>) -> Result<Basis, EventsError> {
        let nf = self.free.len();
        let sub = |a: &Mat<f64>| Mat::from_fn(nf, nf, |i, j| a[(self.free[i], self.free[j])]);
        Basis::new(sub(m), self.keff.clone(), c.map(sub))
    }

    /// The loads `loads` of the condensed system: `f − K_·h b_h`, each
    /// mapped by [`load`](Self::load).
    fn loads(&self, loads: &Loads, k: impl Fn(usize, usize) -> f64) -> Loads {
        loads.held(k, &self.fixed, |x| self.load(x))
    }

    /// The free dofs' flow without events, `M_ff` and `C_ff` of `dy`, the
    /// condensed stiffness and loads: as [`ModalFlow::new`] of that system
    /// (a piecewise-linear series refused, [`EventsError::Profile`]).
    pub fn flow(&self, dy: &Dynamics) -> Result<ModalFlow, EventsError> {
        let loads = Loads::without_series(dy)?;
        let basis = self.basis(&dense(&dy.mass), dy.damping.as_ref().map(dense).as_ref())?;
        Ok(ModalFlow::with_loads(&basis, &self.loads(&loads, |i, j| dy.stiffness.get(i, j))))
    }
}

/// The static LCP of the massless contacts: on `K_ZZ⁻¹`, in `Z`'s
/// coordinates (the contacts in their order), and `K_ZZ⁻¹`.
pub(super) fn static_delassus(k: &Mat<f64>, zero: &[usize], sites: &[Site]) -> Result<(MultiProjection, Mat<f64>), EventsError> {
    let nz = zero.len();
    let kzz = Mat::from_fn(nz, nz, |i, j| k[(zero[i], zero[j])]);
    let inv = spd_inverse(&kzz).ok_or_else(not_spd)?;
    let dofs: Vec<usize> = sites.iter().map(|s| zero.iter().position(|&z| z == s.dof).expect("a massless contact dof")).collect();
    let columns = dofs.iter().map(|&p| (0..nz).map(|r| inv[(r, p)]).collect()).collect();
    let lcp = MultiProjection::new(dofs, columns)?;
    Ok((lcp, inv))
}

impl EventDriven {
    fn is_zero(&self, d: usize) -> bool {
        self.zero.binary_search(&d).is_ok()
    }

    /// The phase of `holds` with massless contacts (module docs).
    pub(super) fn build_static(&self, holds: &[Hold], piece: &Piece) -> Result<System, EventsError> {
        let (n, k) = (self.n, &self.k);
        let held = self.held_values(holds);
        let cond: Vec<usize> = self.zero.iter().copied().filter(|d| !held.iter().any(|h| h.0 == *d)).collect();
        // The held dofs are massless: the free ones are the massive dofs.
        let cd = Condensation::of(k, held, cond)?;
        let loads = cd.loads(&self.loads, |i, j| k[(i, j)]);
        let basis = self.basis(holds, || cd.basis(&self.m, self.c.as_ref()))?;
        let flow = ModalFlow::with_loads(&basis, &loads);
        let Condensation { free, cond, fixed: held, g, .. } = cd;
        let (nf, ns) = (free.len(), cond.len());
        let zeros = vec![0.0; nf];
        let (mut fns, mut quiet, mut watch) = (Vec::new(), Vec::new(), Vec::new());
        for (j, s) in self.sites.iter().enumerate() {
            let Some(p) = cond.iter().position(|&d| d == s.dof) else { continue };
            // q_c = Σ_i G_pi (f_i(t) − K_iR q_R − K_iA q_A), i over S.
            let row: Vec<f64> = (0..nf).map(|r| -(0..ns).map(|i| g[(p, i)] * k[(cond[i], free[r])]).sum::<f64>()).collect();
            let mut position = flow.linear(&row, &zeros);
            let mut coef = vec![0.0; n];
            for i in 0..ns {
                coef[cond[i]] += g[(p, i)];
                for &(a, xa) in &held {
                    position.constant -= g[(p, i)] * k[(cond[i], a)] * xa;
                }
            }
            self.add_loads(&mut position, &coef);
            self.gap_watches(j, &position, (&mut fns, &mut quiet, &mut watch));
        }
        let mut forces = Vec::new();
        for h in holds {
            // r_c = (K q − f)_c with q_S condensed.
            let c = self.sites[h.contact].dof;
            let kcs_g: Vec<f64> = (0..ns).map(|i| (0..ns).map(|s| k[(c, cond[s])] * g[(s, i)]).sum()).collect();
            let row: Vec<f64> = (0..nf).map(|r| k[(c, free[r])] - (0..ns).map(|i| kcs_g[i] * k[(cond[i], free[r])]).sum::<f64>()).collect();
            let mut f = flow.linear(&row, &zeros);
            let mut coef = vec![0.0; n];
            coef[c] -= 1.0;
            for i in 0..ns {
                coef[cond[i]] += kcs_g[i];
            }
            for &(a, xa) in &held {
                f.constant += (k[(c, a)] - (0..ns).map(|i| kcs_g[i] * k[(cond[i], a)]).sum::<f64>()) * xa;
            }
            self.add_loads(&mut f, &coef);
            self.held_force(*h, f, &mut forces, (&mut fns, &mut quiet, &mut watch));
        }
        let mut sys = System { flow, free, held, fns, quiet, watch, forces, cond, g };
        sys.set_piece(piece);
        Ok(sys)
    }

    /// The condensed dofs' `q_S = K_SS⁻¹ (f_S(t) − K_SR q_R − K_SA q_A)` and
    /// `v_S = K_SS⁻¹ (f_S'(t) − K_SR v_R)` into `q`, `v` (the others set).
    pub(super) fn condensed_into(&self, sys: &System, q: &mut [f64], v: &mut [f64]) {
        let (t, k, n) = (self.t, &self.k, self.n);
        let cond = &sys.cond;
        for (p, &d) in cond.iter().enumerate() {
            let (mut x, mut y) = (0.0, 0.0);
            for (i, &ci) in cond.iter().enumerate() {
                let (mut w, mut dw) = (self.loads.value(ci, t), self.loads.rate(ci, t, &self.piece));
                for r in 0..n {
                    if !cond.contains(&r) {
                        w -= k[(ci, r)] * q[r];
                        dw -= k[(ci, r)] * v[r];
                    }
                }
                x += sys.g[(p, i)] * w;
                y += sys.g[(p, i)] * dw;
            }
            (q[d], v[d]) = (x, y);
        }
    }

    /// [`settle`](EventDriven::settle) with massless contacts (module docs):
    /// the static LCP decides which contacts are at a bound, the rate LCP
    /// which of those without force stay.
    pub(super) fn settle_static(&mut self, t: f64, q: &mut [f64], v: &mut [f64], primary: Option<(usize, Bound)>, w: &mut Work) -> Result<(), EventsError> {
        let (n, nz, kc) = (self.n, self.zero.len(), self.sites.len());
        let piece = &mut w.piece;
        self.loads.piece_into(t, piece);
        // K_ZZ⁻¹ (f_Z − K_ZR q_R) and its rate.
        let (b, db) = (&mut w.b, &mut w.db);
        for x in [&mut *b, &mut *db] {
            x.clear();
            x.resize(nz, 0.0);
        }
        for (i, &d) in self.zero.iter().enumerate() {
            b[i] = self.loads.value(d, t);
            db[i] = self.loads.rate(d, t, piece);
            for r in (0..n).filter(|&r| !self.is_zero(r)) {
                b[i] -= self.k[(d, r)] * q[r];
                db[i] -= self.k[(d, r)] * v[r];
            }
        }
        let apply = |x: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend((0..nz).map(|i| (0..nz).map(|j| self.kzz_inv[(i, j)] * x[j]).sum::<f64>()));
        };
        let (y, dy) = (&mut w.ys, &mut w.dys);
        apply(b, y);
        apply(db, dy);
        let pos = &mut w.pos;
        pos.clear();
        pos.extend_from_slice(self.delassus.dofs());
        let (lo, hi) = (&mut w.lo, &mut w.hi);
        lo.clear();
        lo.extend(self.sites.iter().map(|s| s.lo));
        hi.clear();
        hi.extend(self.sites.iter().map(|s| s.hi));
        self.delassus.project(y, lo, hi)?;
        let r0 = &mut w.mu;
        r0.clear();
        r0.extend_from_slice(self.delassus.multipliers());
        // Which bound each contact is at (the located one at the bound it
        // reached), and whether its static force presses it there (a
        // multiplier of the other sign is round-off of a landing).
        let at = &mut w.at;
        at.clear();
        at.resize(kc, None);
        let pressed = &mut w.pressed;
        pressed.clear();
        pressed.resize(kc, false);
        for (j, s) in self.sites.iter().enumerate() {
            let (yc, tol) = (y[pos[j]], 1e-12 * s.scale);
            at[j] = match primary {
                Some((p, b)) if p == j => Some(b == Bound::Upper),
                _ if yc - s.lo <= tol => Some(false),
                _ if s.hi - yc <= tol => Some(true),
                _ => None,
            };
            pressed[j] = match at[j] {
                Some(false) => r0[j] > 0.0,
                Some(true) => r0[j] < 0.0,
                None => false,
            };
        }
        // The rates: pressed contacts stay (an equality), those at a bound
        // without force may leave it.
        // (In the static LCP's bounds: not used again.)
        let (rlo, rhi) = (lo, hi);
        super::unbounded(rlo, rhi, kc);
        for j in 0..kc {
            match at[j] {
                // Pressed, or equal bounds (a bilateral constraint).
                Some(_) if pressed[j] || self.sites[j].lo == self.sites[j].hi => (rlo[j], rhi[j]) = (0.0, 0.0),
                Some(false) => rlo[j] = 0.0,
                Some(true) => rhi[j] = 0.0,
                None => {}
            }
        }
        let before = &mut w.vbefore;
        before.clear();
        before.extend(self.sites.iter().map(|s| v[s.dof]));
        self.delassus.project(dy, rlo, rhi)?;
        let mu = self.delassus.multipliers();
        let dscale = dy.iter().fold(0.0f64, |a, x| a.max(x.abs())).max(f64::MIN_POSITIVE);
        let holds = &mut w.holds;
        holds.clear();
        for j in 0..kc {
            let Some(upper) = at[j] else { continue };
            let bilateral = self.sites[j].lo == self.sites[j].hi;
            let leaving = !bilateral && !pressed[j] && mu[j] == 0.0 && dy[pos[j]].abs() > 1e-12 * dscale;
            if !leaving {
                holds.push(Hold { contact: j, upper });
            }
        }
        // At a start (no event located) the massless dofs' entries of the
        // state given are not data: they take the static solution and its
        // rate (enter reads them: an entry on a bound with a speed away
        // from it would mark that gap exactly 0 at the base; docs/theory.md
        // §9.3). After an event they are the condensed ones already.
        if primary.is_none() {
            for (i, &d) in self.zero.iter().enumerate() {
                (q[d], v[d]) = (y[i], dy[i]);
            }
        }
        let was_held = &mut w.held_before;
        was_held.clear();
        was_held.extend((0..kc).map(|j| self.holds.iter().any(|h| h.contact == j)));
        if primary.is_some() {
            for j in 0..kc {
                let now = holds.iter().any(|h| h.contact == j);
                if now && !was_held[j] {
                    self.events.push(EventRecord { t, kind: EventKind::Impact, contact: j, velocity_before: before[j], velocity_after: 0.0, impulse: 0.0 });
                } else if was_held[j] && !now {
                    self.events.push(EventRecord { t, kind: EventKind::Release, contact: j, velocity_before: 0.0, velocity_after: 0.0, impulse: 0.0 });
                }
            }
        }
        for h in holds.iter() {
            let s = &self.sites[h.contact];
            (q[s.dof], v[s.dof]) = (if h.upper { s.hi } else { s.lo }, 0.0);
        }
        self.enter(holds, q, v, t, false)?;
        self.t = t;
        Ok(())
    }
}
