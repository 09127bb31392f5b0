//! # signorini-reduce
//!
//! A clamped P1 bar reduced to its contact dof and three modes, checked
//! against the closed-form modes of the fixed–fixed lumped bar:
//!
//! ```
//! use signorini_fem::{Bar, BarMass, RightEnd};
//! use signorini_reduce::{Keep, Reduction};
//!
//! // 8 elements (h = 1/8, c = 1), clamped at x = 1, lumped mass, contact at node 0.
//! let bar = Bar::new(1.0, 8, 1.0, RightEnd::Clamped)?;
//! let (k, m) = (bar.stiffness(), bar.mass(BarMass::Lumped));
//! let red = Reduction::new(&k, &m, &[0], Keep::Modes(3))?;
//! assert_eq!(red.dofs(), 1 + 3); // the contact, then the modes
//! // Contact held, the 7 interior nodes are the fixed–fixed lumped bar:
//! // ω_j² = (4c²/h²) sin²(jπ/16).
//! for (j, w2) in red.modes().iter().enumerate() {
//!     let want = 4.0 * 64.0 * ((j + 1) as f64 * std::f64::consts::PI / 16.0).sin().powi(2);
//!     assert!((w2 - want).abs() <= 1e-10 * want, "mode {}: {w2} != {want}", j + 1);
//! }
//! // The contact dof is massless in the reduced model, and the explicit
//! // central difference's limit on it is 2/ω_3.
//! assert_eq!(red.mass().get(0, 0), 0.0);
//! assert!((red.cfl_limit() - 2.0 / red.modes()[2].sqrt()).abs() < 1e-12);
//!
//! // With every interior mode kept the basis is invertible: a field comes
//! // back from its reduced coordinates.
//! let all = Reduction::new(&k, &m, &[0], Keep::Modes(7))?;
//! let u: Vec<f64> = (0..8).map(|i| 0.1 + bar.node(i) * (1.0 - bar.node(i))).collect();
//! let mut back = vec![0.0; 8];
//! all.reconstruct(&all.project_state(&u), &mut back);
//! assert!(u.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-12));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Reduced models with a massless contact boundary (docs/theory.md §2.5):
//! the massless-boundary component mode synthesis of Monjaraz Tec, Gross &
//! Krack (Comput. Struct. 260 (2022) 106698) for a pencil `(K, M)` and a
//! list of contact dofs `b` (the other dofs `i`):
//!
//! * fixed-interface modes `Kᵢᵢ φ_k = ω_k² Mᵢᵢ φ_k` (contacts held, `Φᵀ Mᵢᵢ Φ = I`),
//!   the `r` lowest kept ([`Keep`]);
//! * static constraint modes `Ψ = −Kᵢᵢ⁻¹ Kᵢ_b`;
//! * coordinates `q = (u_b, p)`: the contact displacements (physical) and
//!   the modal coordinates of the interior displacement, `p = Φ_rᵀ Mᵢᵢ uᵢ`;
//!   the basis `u = T q`, `T = [[I, 0], [(I − Φ_r Φ_rᵀ Mᵢᵢ) Ψ, Φ_r]]`;
//! * `K_r = Tᵀ K T = [[K̂_bb + Gᵀ Λ_r⁻¹ G, Gᵀ], [G, Λ_r]]` with
//!   `K̂_bb = K_bb + K_bᵢ Ψ` (the statically condensed stiffness) and
//!   `G = Φ_rᵀ Kᵢ_b`; `M_r = [[0, 0], [0, I_r]]`: the residual mass of the
//!   constraint modes (`Ψᵀ Pᵀ Mᵢᵢ P Ψ`, `P = I − Φ_r Φ_rᵀ Mᵢᵢ`, MacNeal's
//!   massless residual) and the contact rows of `M` are dropped, so the
//!   contact dofs are massless, exactly the structure of the `mod` masses.
//!
//! With every interior mode kept `P = 0`, `T` is invertible and, for a
//! parent whose contact rows of `M` are zero, `(K_r, M_r) = (Tᵀ K T, Tᵀ M T)`
//! exactly: the reduced model is the parent in other coordinates.
//!
//! The contacts are the reduced dofs `0..nb` in the given order, the modes
//! follow. Construction is dense (faer's Cholesky and symmetric eigensolver);
//! [`Reduction::reconstruct`] and [`Reduction::reconstruct_dof`] allocate
//! nothing.
//!
//! Architecture invariant: no IO, no time stepping, no contact logic.

use faer::linalg::solvers::Solve;
use faer::{Mat, Par, Side};
use signorini_fem::SymBand;
use std::f64::consts::PI;

/// Which fixed-interface modes to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Keep {
    /// The `r` lowest (`1 <= r <=` the number of interior dofs).
    Modes(usize),
    /// Every mode with `ω_k <= 2π f` (`f` in Hz, at or above the first
    /// mode's frequency `ω_1 / 2π`).
    CutoffHz(f64),
}

/// Errors of this crate (each names the field and the allowed range).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReduceError {
    /// A parameter outside its allowed range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// The parameter's name (`modes`, `cutoff_hz`, `contacts`).
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// A block of the parent that must be positive definite is not.
    #[error("{field}: {why}")]
    NotDefinite {
        /// `mass` or `stiffness`.
        field: &'static str,
        /// Why, in words.
        why: &'static str,
    },
}

/// A massless-boundary Craig–Bampton reduction of `(K, M)` (see the crate
/// documentation for the formulas).
#[derive(Clone, Debug)]
pub struct Reduction {
    n: usize,
    contacts: Vec<usize>,
    /// For each full dof: `Ok(k)` contact `k`, `Err(i)` interior row `i`.
    slot: Vec<Result<usize, usize>>,
    omega2: Vec<f64>,
    interior_modes: usize,
    k_r: SymBand,
    m_r: SymBand,
    /// Interior rows of `T`, row-major `nᵢ × (nb + r)`.
    t_int: Vec<f64>,
    /// `Φ_rᵀ Mᵢᵢ`, row-major `r × nᵢ`.
    proj: Vec<f64>,
    kappa_free: f64,
}

/// Eigenvalues (ascending) and orthonormal eigenvectors of the symmetric
/// `c` (lower triangle read) by faer's tridiagonal QR algorithm at every
/// size. faer 0.24's default switches to divide and conquer at n >= 128,
/// which on the graded pencils of a fine beam (eigenvalues over ten
/// decades) returned orthonormal vectors that were not eigenvectors
/// (relative residual 3e-4 of the largest eigenvalue at n = 151, and the
/// reduced contact stiffness 4e-4 off); the QR path keeps the residual at
/// round-off (tests/it/reduction.rs, a fine beam).
fn sym_eigen(c: &Mat<f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors, SelfAdjointEvdParams};
    let n = c.nrows();
    let mut params: faer::Spec<SelfAdjointEvdParams, f64> = faer::Spec::new(<SelfAdjointEvdParams as faer::Auto<f64>>::auto());
    params.recursion_threshold = usize::MAX;
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let mut buf = MemBuffer::new(self_adjoint_evd_scratch::<f64>(n, ComputeEigenvectors::Yes, Par::Seq, params));
    self_adjoint_evd(c.as_ref(), s.as_mut(), Some(u.as_mut()), Par::Seq, MemStack::new(&mut buf), params).ok()?;
    Some(((0..n).map(|j| s.column_vector()[j]).collect(), u))
}

fn dense(a: &SymBand, rows: &[usize], cols: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), cols.len(), |i, j| a.get(rows[i], cols[j]))
}

impl Reduction {
    /// Builds the reduction of `(k, m)` with the contact dofs `contacts`
    /// (distinct, in range, fewer than `n`), keeping the modes `keep`.
    ///
    /// Errors: `contacts` empty, repeated, out of range or covering every
    /// dof; `modes` outside `1..=nᵢ`; `cutoff_hz` not finite or below the
    /// first mode; `Mᵢᵢ` or `Kᵢᵢ` not positive definite. Panics if `k` and
    /// `m` differ in size (programmer error).
    #[track_caller]
    pub fn new(k: &SymBand, m: &SymBand, contacts: &[usize], keep: Keep) -> Result<Self, ReduceError> {
        let n = k.n();
        assert_eq!(m.n(), n, "K and M differ in size");
        let bad = |field: &'static str, value: f64, allowed: String| Err(ReduceError::Invalid { field, value, allowed });
        if contacts.is_empty() || contacts.len() >= n {
            return bad("contacts", contacts.len() as f64, format!("between 1 and {} contact dofs", n.saturating_sub(1)));
        }
        for (j, &c) in contacts.iter().enumerate() {
            if c >= n {
                return bad("contacts", c as f64, format!("dofs in 0..{n}"));
            }
            if contacts[..j].contains(&c) {
                return bad("contacts", c as f64, "distinct dofs".into());
            }
        }
        let nb = contacts.len();
        let mut slot = vec![Err(0); n];
        for (j, &c) in contacts.iter().enumerate() {
            slot[c] = Ok(j);
        }
        let interior: Vec<usize> = (0..n).filter(|d| slot[*d].is_err()).collect();
        for (i, &d) in interior.iter().enumerate() {
            slot[d] = Err(i);
        }
        let ni = interior.len();
        if let Keep::Modes(r) = keep {
            if r == 0 || r > ni {
                return bad("modes", r as f64, format!("1..={ni} (the interior dofs, contacts held)"));
            }
        }
        if let Keep::CutoffHz(f) = keep {
            if !(f.is_finite() && f > 0.0) {
                return bad("cutoff_hz", f, "finite and > 0".into());
            }
        }
        let (mii, kii, kib, kbb) = (dense(m, &interior, &interior), dense(k, &interior, &interior), dense(k, &interior, contacts), dense(k, contacts, contacts));
        // Fixed-interface modes: Mᵢᵢ = L Lᵀ, L⁻¹ Kᵢᵢ L⁻ᵀ = V Λ Vᵀ, Φ = L⁻ᵀ V.
        let llt = mii.llt(Side::Lower).map_err(|_| ReduceError::NotDefinite { field: "mass", why: "the mass on the dofs other than the contacts must be positive definite" })?;
        let l = llt.L().to_owned();
        let mut linv = Mat::<f64>::identity(ni, ni);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), Par::Seq);
        let c = &linv * &kii * linv.transpose();
        let c = Mat::from_fn(ni, ni, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
        let (lam, evecs) = sym_eigen(&c).ok_or(ReduceError::NotDefinite { field: "stiffness", why: "the fixed-interface eigenproblem did not converge" })?;
        if !(lam[0] > 0.0) {
            return Err(ReduceError::NotDefinite { field: "stiffness", why: "the stiffness on the dofs other than the contacts must be positive definite (hold the contacts: no rigid motion left)" });
        }
        let r = match keep {
            Keep::Modes(r) => r,
            Keep::CutoffHz(f) => {
                let w = 2.0 * PI * f;
                let first = lam[0].sqrt() / (2.0 * PI);
                if w * w < lam[0] {
                    return bad("cutoff_hz", f, format!(">= the first fixed-interface mode, {first} Hz"));
                }
                lam.iter().take_while(|&&l| l <= w * w).count()
            }
        };
        let phi = linv.transpose() * evecs.subcols(0, r);
        let omega2 = lam[..r].to_vec();
        // Static constraint modes Ψ = −Kᵢᵢ⁻¹ Kᵢ_b.
        let kllt = kii.llt(Side::Lower).map_err(|_| ReduceError::NotDefinite { field: "stiffness", why: "the stiffness on the dofs other than the contacts must be positive definite" })?;
        let psi = -kllt.solve(&kib);
        let khat = &kbb + kib.transpose() * &psi;
        let g = phi.transpose() * &kib; // r × nb
        let proj = phi.transpose() * &mii; // r × nᵢ
                                           // Interior rows of T: [(I − Φ Φᵀ Mᵢᵢ) Ψ, Φ].
        let ppsi = &psi - &phi * (&proj * &psi);
        let nr = nb + r;
        let mut t_int = vec![0.0; ni * nr];
        for i in 0..ni {
            for j in 0..nb {
                t_int[i * nr + j] = ppsi[(i, j)];
            }
            for j in 0..r {
                t_int[i * nr + nb + j] = phi[(i, j)];
            }
        }
        let ginv = Mat::from_fn(r, nb, |a, j| g[(a, j)] / omega2[a]);
        let kbb_r = &khat + g.transpose() * &ginv;
        let mut k_r = SymBand::zeros(nr, nr - 1);
        let mut m_r = SymBand::zeros(nr, nr - 1);
        for a in 0..nb {
            for b in 0..=a {
                k_r.set(a, b, 0.5 * (kbb_r[(a, b)] + kbb_r[(b, a)]));
            }
            for j in 0..r {
                k_r.set(nb + j, a, g[(j, a)]);
            }
        }
        for j in 0..r {
            k_r.set(nb + j, nb + j, omega2[j]);
            m_r.set(nb + j, nb + j, 1.0);
        }
        // The free-contact pencil: the massless contacts eliminated statically,
        // S = Λ_r − G K_bb,r⁻¹ Gᵀ.
        let kbb_llt = kbb_r.llt(Side::Lower).map_err(|_| ReduceError::NotDefinite { field: "stiffness", why: "the condensed contact stiffness must be positive definite" })?;
        let s = Mat::from_fn(r, r, |a, b| if a == b { omega2[a] } else { 0.0 }) - &g * kbb_llt.solve(g.transpose());
        let s = Mat::from_fn(r, r, |a, b| 0.5 * (s[(a, b)] + s[(b, a)]));
        let ev = s.self_adjoint_eigenvalues(Side::Lower).map_err(|_| ReduceError::NotDefinite { field: "stiffness", why: "the reduced pencil's eigenproblem did not converge" })?;
        let kappa_free = ev.iter().fold(0.0_f64, |a, &x| a.max(x));
        let proj = (0..r * ni).map(|x| proj[(x / ni, x % ni)]).collect();
        Ok(Self { n, contacts: contacts.to_vec(), slot, omega2, interior_modes: ni, k_r, m_r, t_int, proj, kappa_free })
    }

    /// Size `n` of the parent.
    pub fn parent_dofs(&self) -> usize {
        self.n
    }

    /// Size `nb + r` of the reduced system.
    pub fn dofs(&self) -> usize {
        self.contacts.len() + self.omega2.len()
    }

    /// Number of interior dofs `nᵢ = n − nb` (the most modes there are).
    pub fn interior_dofs(&self) -> usize {
        self.interior_modes
    }

    /// The kept fixed-interface eigenvalues `ω_k²`, ascending (`r` of them).
    pub fn modes(&self) -> &[f64] {
        &self.omega2
    }

    /// The reduced stiffness `K_r` (dense, stored with full half-bandwidth).
    pub fn stiffness(&self) -> &SymBand {
        &self.k_r
    }

    /// The reduced mass `M_r = diag(0, I_r)` (contact rows zero), with the
    /// same storage shape as [`Reduction::stiffness`].
    pub fn mass(&self) -> &SymBand {
        &self.m_r
    }

    /// The contact dofs of the parent, in order; contact `k` is reduced dof `k`.
    pub fn contacts(&self) -> &[usize] {
        &self.contacts
    }

    /// The reduced index of parent dof `dof` if it is a contact dof.
    pub fn reduced_contact(&self, dof: usize) -> Option<usize> {
        self.slot.get(dof).and_then(|s| s.ok())
    }

    /// `κ_r`, the largest eigenvalue of the reduced pencil in either contact
    /// state: contacts held (the pencil `(Λ_r, I)`, largest eigenvalue `ω_r²`)
    /// or free (the massless contacts condensed statically,
    /// [`Reduction::kappa_free`]). Since the condensed pencil lies below
    /// `Λ_r`, `κ_r = ω_r²`, the largest kept fixed-interface eigenvalue.
    pub fn kappa(&self) -> f64 {
        self.omega2.last().copied().unwrap_or(0.0).max(self.kappa_free)
    }

    /// The largest finite eigenvalue of `(K_r, M_r)` with the contacts free:
    /// of `S = Λ_r − G K_bb,r⁻¹ Gᵀ` (the massless contacts condensed).
    pub fn kappa_free(&self) -> f64 {
        self.kappa_free
    }

    /// The exact stability limit of the explicit central difference with
    /// quasi-static massless contacts on the reduced model: `2 / sqrt(κ_r)
    /// = 2 / ω_r` (the same rule as the full model's `cd-massless`, whose
    /// limit is set by the pencil with the contact held).
    pub fn cfl_limit(&self) -> f64 {
        2.0 / self.kappa().sqrt()
    }

    /// `u = T q`: the full field from the reduced coordinates. Allocates
    /// nothing. Panics on wrong lengths (programmer error).
    #[track_caller]
    pub fn reconstruct(&self, q: &[f64], out: &mut [f64]) {
        assert!(q.len() == self.dofs() && out.len() == self.n, "length mismatch");
        for (d, o) in out.iter_mut().enumerate() {
            *o = self.row(d, q);
        }
    }

    /// One entry `(T q)_dof` of the full field (an observer that needs one
    /// dof reconstructs only its row of `T`).
    #[track_caller]
    pub fn reconstruct_dof(&self, dof: usize, q: &[f64]) -> f64 {
        assert!(q.len() == self.dofs() && dof < self.n, "length mismatch");
        self.row(dof, q)
    }

    #[inline]
    fn row(&self, d: usize, q: &[f64]) -> f64 {
        match self.slot[d] {
            Ok(k) => q[k],
            Err(i) => {
                let nr = self.dofs();
                self.t_int[i * nr..(i + 1) * nr].iter().zip(q).map(|(a, b)| a * b).sum()
            }
        }
    }

    /// `Tᵀ f`: a load (or any covector) of the parent in reduced coordinates.
    #[track_caller]
    pub fn project_vector(&self, f: &[f64]) -> Vec<f64> {
        assert_eq!(f.len(), self.n, "length mismatch");
        let nr = self.dofs();
        let mut out = vec![0.0; nr];
        for (d, &fd) in f.iter().enumerate() {
            match self.slot[d] {
                Ok(k) => out[k] += fd,
                Err(i) => out.iter_mut().zip(&self.t_int[i * nr..(i + 1) * nr]).for_each(|(o, t)| *o += t * fd),
            }
        }
        out
    }

    /// Reduced coordinates of a displacement or velocity field `u` of the
    /// parent (initial data): `u_b` at the contacts and `p = Φ_rᵀ Mᵢᵢ uᵢ`,
    /// the `Mᵢᵢ`-orthogonal projection of the interior field on the kept
    /// modes. A left inverse of `T` (`q = project_state(T q)`), the identity
    /// inverse of `T` with every mode kept.
    #[track_caller]
    pub fn project_state(&self, u: &[f64]) -> Vec<f64> {
        assert_eq!(u.len(), self.n, "length mismatch");
        let (nb, r, ni) = (self.contacts.len(), self.omega2.len(), self.interior_modes);
        let ui: Vec<f64> = (0..self.n).filter(|d| self.slot[*d].is_err()).map(|d| u[d]).collect();
        let mut out: Vec<f64> = self.contacts.iter().map(|&c| u[c]).collect();
        out.extend((0..r).map(|a| self.proj[a * ni..(a + 1) * ni].iter().zip(&ui).map(|(x, y)| x * y).sum::<f64>()));
        debug_assert_eq!(out.len(), nb + r);
        out
    }
}
