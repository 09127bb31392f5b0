//! What an event-driven run reports: its events ([`EventRecord`], of an
//! [`EventKind`]) and why it refused a problem or stopped
//! ([`EventsError`]). Plain data that the crate root names too (the
//! stepper's `events`, the crate's error): it depends on no other module.

/// What happened at an event (`events.csv`'s `kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// An impact (Newton's law).
    Impact,
    /// A held contact's force reached 0: it leaves its bound.
    Release,
    /// Impacts accumulated (chattering): the contact comes to rest.
    Accumulation,
}

impl EventKind {
    /// The name in `events.csv`: `impact`, `release`, `accumulation`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Impact => "impact",
            Self::Release => "release",
            Self::Accumulation => "accumulation",
        }
    }
}

/// One event of an [`EventDriven`](super::EventDriven) run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord {
    /// Its time.
    pub t: f64,
    /// What happened.
    pub kind: EventKind,
    /// The contact (its index in `Dynamics::contacts`).
    pub contact: usize,
    /// The contact dof's velocity before.
    pub velocity_before: f64,
    /// And after.
    pub velocity_after: f64,
    /// The impulse (the contact force's integral over the instant; `r` of
    /// `M q'' + C q' + K q = f + Σ r_i e_{c_i}`: positive at a lower bound).
    pub impulse: f64,
}

/// Why a problem has no exact event-driven solution here.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EventsError {
    /// The mass matrix is not positive definite.
    #[error("mass: not positive definite")]
    MassNotDefinite,
    /// An entry of `M`, `K` or `C` that is NaN or infinite.
    #[error("{matrix}[{row}][{col}] = {value}: allowed: finite")]
    NotFinite {
        /// `"mass"`, `"stiffness"` or `"damping"`.
        matrix: &'static str,
        /// The entry's row.
        row: usize,
        /// The entry's column.
        col: usize,
        /// The entry.
        value: f64,
    },
    /// A restitution other than 0 at a contact dof without mass (a
    /// reduced model's or mass redistribution's contact boundary): its
    /// force is static, it lands without an impact.
    #[error("contacts[{contact}].restitution = {restitution}: a massless contact dof lands on its bound without an impact (its force is statically condensed), so no restitution acts there; allowed: 0 (event-driven(0))")]
    MasslessRestitution {
        /// The contact.
        contact: usize,
        /// Its restitution.
        restitution: f64,
    },
    /// A non-classical damping whose first-order form has no
    /// well-conditioned basis of real two-dimensional invariant subspaces
    /// here: a complex pair repeated three or more times with fewer
    /// eigenvectors than its multiplicity, a real eigenvalue repeated more
    /// than twice without as many eigenvectors, an odd count of real
    /// eigenvalues left unpaired, or a basis whose condition exceeds 1e8
    /// (a critically damped mode, a Jordan block of two, and a defective
    /// complex pair, a complex Jordan block of two, are taken:
    /// docs/theory.md §9.1).
    #[error("damping: the first-order form of the non-classical damping C has no well-conditioned basis of real invariant planes (the condition number ‖T‖∞‖T⁻¹‖∞ of its modal basis is {condition:e}, allowed up to 1e8; inf: no basis, e.g. a real Jordan block of three or more): no exact modal flow; allowed: classical damping (e.g. Rayleigh C = a M + b K) or a non-classical one whose eigenvalues are distinct, critically damped pairs (a Jordan block of two), defective complex pairs (a complex Jordan block of two), or repeated with as many independent eigenvectors as their multiplicity")]
    Defective {
        /// `‖T‖∞ ‖T⁻¹‖∞` of the modal basis (infinite: no basis).
        condition: f64,
    },
    /// A load profile without a closed-form particular solution here.
    #[error("forcing[{index}]: a piecewise-linear series is taken piece by piece by the event-driven run (EventDriven, EventStepper), not by one ModalFlow; allowed here: constant loads, sine or harmonics")]
    Profile {
        /// The forcing term.
        index: usize,
    },
    /// The symmetric eigensolver failed.
    #[error("the modal decomposition of (K, M) failed")]
    Eigen,
    /// A restitution outside [0, 1].
    #[error("contacts[{contact}].restitution = {restitution}: allowed [0, 1]")]
    Restitution {
        /// The contact.
        contact: usize,
        /// Its restitution.
        restitution: f64,
    },
    /// More events than allowed.
    #[error("{events} events by t = {t} (max_events): the run stops there, the events so far are kept; if the impacts are real, raise the limit with the scheme's second parameter: scheme = \"event-driven(E,MAX_EVENTS)\" (default 1e7, at most 1e12); impacts that come ever faster without accumulating (an elastic contact, E = 1, pressed on its stop under damping: its hops shrink only as e^(-rt), r = C_cc/(3 M_cc)) gain a fixed time, ln(10)/r, per tenfold limit: use a restitution below 1 or a time stepper there (docs/theory.md §9.3)")]
    TooManyEvents {
        /// Where it stopped.
        t: f64,
        /// Events taken.
        events: usize,
    },
    /// Events repeat at one instant without the time advancing (a cycle
    /// of releases and impacts that the rules do not settle).
    #[error("{events} events at t = {t} without the time advancing (the last: {cycle}): the run stops there, the events so far are kept; this is a defect of the event rules for this case, please report it with the scene")]
    NoProgress {
        /// Where it stalled.
        t: f64,
        /// Events at that instant.
        events: usize,
        /// The last events, in words.
        cycle: String,
    },
    /// The poll of [`crate::Stepper::set_interrupt`] asked the run to
    /// stop: the state is whole, at `t` (inside an output step).
    #[error("interrupted at t = {t}")]
    Interrupted {
        /// The time the run stopped at.
        t: f64,
    },
    /// The event search took too many steps (a contact grazing its bound).
    #[error("the event search stopped at t = {t} after {steps} steps (a contact grazing its bound without reaching it)")]
    NoConvergence {
        /// Where it stopped.
        t: f64,
        /// Steps taken.
        steps: usize,
    },
    /// The contacts' Delassus matrix could not be set up or solved (two
    /// contacts on one dof, say).
    #[error("contacts: {0}")]
    Contacts(String),
    /// The start is outside a contact's bounds.
    #[error("contacts[{contact}]: the initial state q = {q} is outside [{lo}, {hi}]")]
    Outside {
        /// The contact.
        contact: usize,
        /// Its dof's displacement.
        q: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
}

/// The contacts' solver's error, as [`EventsError::Contacts`] (its message).
impl From<signorini_contact::ContactError> for EventsError {
    fn from(e: signorini_contact::ContactError) -> Self {
        EventsError::Contacts(e.to_string())
    }
}
