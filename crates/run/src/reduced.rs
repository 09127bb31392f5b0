//! Reduced models with a massless contact boundary (docs/theory.md §2.5):
//! a [`Dynamics`] replaced by its massless-boundary Craig–Bampton reduction
//! ([`signorini_reduce::Reduction`]), and an observer adapter that
//! reconstructs the full field only for the observers that need it.
//!
//! The reduced system has the contacts as its dofs `0..nb` (massless, in
//! contact order) and the kept fixed-interface modes after them, so every
//! scheme that accepts a massless contact node and the multi-contact solve
//! run on it unchanged.

use crate::{Observer, RunError, Sample};
use signorini_reduce::{Keep, Reduction};
use signorini_schemes::{Contact, Dynamics, Forcing, Initial};

/// A reduced problem: the reduction, the reduced dynamics and initial state.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// The basis and reduced matrices.
    pub reduction: Reduction,
    /// `(K_r, M_r)`, `Tᵀ F`, `Tᵀ shape` for every forcing, the contacts at
    /// `0..nb`, massless.
    pub dynamics: Dynamics,
    /// The initial state in reduced coordinates
    /// ([`Reduction::project_state`] of displacement and velocity).
    pub initial: Initial,
}

/// Reduces `dy` with initial state `init`, keeping `keep` modes, the
/// contacts of `dy` as the boundary. A parent with massive contacts (the
/// beam's consistent mass) is made massless at the contacts by the method
/// itself (`M_r = diag(0, I)`); a parent with massless contacts (the bar's
/// `mod` family) is reproduced exactly when every mode is kept.
///
/// Refused: damping (`damping`, not reduced here), and the reduction's own
/// errors ([`signorini_reduce::ReduceError`], naming `modes`, `cutoff_hz`).
pub fn reduce(dy: &Dynamics, init: &Initial, keep: Keep) -> Result<Reduced, RunError> {
    if dy.damping.is_some() {
        return Err(RunError::NotAllowed { field: "damping", allowed: "none with a reduced model" });
    }
    let dofs: Vec<usize> = dy.contacts.iter().map(|c| c.dof).collect();
    let reduction = Reduction::new(&dy.stiffness, &dy.mass, &dofs, keep)?;
    // The contacts at 0..nb, massless, with their own bounds, restitution and stiffness.
    let contacts: Vec<Contact> = dy
        .contacts
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mut c = *c;
            (c.dof, c.massless) = (k, true);
            c
        })
        .collect();
    let dynamics = Dynamics::new(reduction.mass().clone(), reduction.stiffness().clone(), reduction.project_vector(&dy.load), contacts)
        .with_forcing(dy.forcing.iter().map(|f| Forcing { shape: reduction.project_vector(&f.shape), time: f.time.clone() }).collect());
    let initial = Initial { u: reduction.project_state(&init.u), v: reduction.project_state(&init.v) };
    Ok(Reduced { reduction, dynamics, initial })
}

/// Which part of the full field an observer reads.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Need {
    /// Every dof (e.g. [`crate::NormObserver`]).
    Full,
    /// Only these parent dofs (e.g. a [`crate::History`] of one dof): only
    /// their rows of `T` are evaluated; the other entries stay zero.
    Dofs(Vec<usize>),
}

/// Feeds an observer of the parent problem from a run of the reduced one:
/// the displacement is reconstructed (`u = T q`, or only the rows in
/// [`Need::Dofs`]) into a buffer allocated at construction; everything
/// else of the [`Sample`] (forces, energy, status) is passed unchanged.
pub struct Reconstruct<'a> {
    reduction: &'a Reduction,
    inner: &'a mut dyn Observer,
    need: Need,
    u: Vec<f64>,
}

impl<'a> Reconstruct<'a> {
    /// Wraps `inner`, which reads the parent dofs in `need`.
    pub fn new(reduction: &'a Reduction, inner: &'a mut dyn Observer, need: Need) -> Self {
        Self { u: vec![0.0; reduction.parent_dofs()], reduction, inner, need }
    }
}

impl Observer for Reconstruct<'_> {
    fn wants_energy(&self) -> bool {
        self.inner.wants_energy()
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        match &self.need {
            Need::Full => self.reduction.reconstruct(s.u, &mut self.u),
            Need::Dofs(d) => {
                for &j in d {
                    self.u[j] = self.reduction.reconstruct_dof(j, s.u);
                }
            }
        }
        self.inner.observe(&Sample { u: &self.u, ..*s })
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.inner.finish()
    }
}
