//! Event-driven integration: the exact flow between events, each event
//! located without a miss, impacts, held phases, releases and accumulations
//! (docs/theory.md §9).
//!
//! **Phases.** At any time a set of contacts is *held* at a bound (the
//! active set). The flow is that of the problem with the held dofs fixed at
//! their bounds: the pencil with their rows and columns removed, the load
//! `f_f − K_fA q_A` on the free dofs ([`ModalFlow`] of the reduced problem,
//! built once per active set and cached). A held contact's force
//!
//! ```text
//! r_a = (M q'' + C q' + K q − f)_a = M_af q_f'' + C_af q_f' + K_af q_f + K_aA q_A − f_a(t)
//! ```
//!
//! is, with `q_f'' = Φ η''` and `η'' = −c η' − k η + Φᵀ(f_f − K_fA q_A)`, a
//! functional of the modal state: `β_i = K_af φ_i − k_i M_af φ_i`,
//! `α_i = C_af φ_i − c_i M_af φ_i`, load terms `M_af M_ff⁻¹ g_f − g_a`.
//! The events are the free contacts reaching a bound (impacts) and the
//! held contacts' forces reaching 0 (releases).
//!
//! **Impacts.** Newton's law for every contact at its bound at once, at
//! velocity level: with `W = M⁻¹` restricted to the contact dofs (the
//! Delassus matrix), the post-impact velocity is the M-projection of the
//! pre-impact one onto `v_c⁺ >= −e_c v_c⁻` (`>= 0` for a contact leaving or
//! held): the exact LCP solved by [`MultiProjection`]. A contact left at
//! rest on its bound (e = 0, or held before) then stays held if the LCP at
//! acceleration level gives it a positive force.
//!
//! **Accumulation.** Each contact keeps its own run of impacts (located or
//! given an impulse by the LCP with another: contacts chattering together
//! each accumulate). Impacts of one contact with `0 < e < 1` whose intervals
//! shrink geometrically (the last ratios equal to 1 %) accumulate at
//! `t∞ = t_k + Δt_k ρ/(1 − ρ)`; once `t∞ − t_k` is below a relative 1e-9
//! of the time, the contact is put at rest on its bound and the event
//! `accumulation` is logged at `t∞`. Its impulse is the one that brings the
//! contact dof to rest (`−v_c/W_cc` for one contact): the remaining
//! impacts' impulses net of the smooth forces over `[t_k, t∞]` (momentum
//! balance); the held phase that follows starts at `t_k`, within the
//! relative 1e-9 of `t∞`. An event the run applies before an
//! accumulation's logged time ends its tail: that row takes the event's
//! time, so the rows are in time order (docs/theory.md §9.3).
//!
//! **Micro-impacts.** A consistent-mass structure pressed on a stop can
//! chatter without accumulating: impacts 1e-9 s apart at speeds of 1e-8,
//! sustained by the neighbouring dofs (a bar with e = 1/2 logged 10⁵ of
//! them per millisecond). An impact slower than 1e-6 of the contact's
//! fastest impact so far (with `0 < e < 1`) ends the run of impacts as an
//! accumulation does: the contact is put at rest (then held if pressed),
//! the `accumulation` logged at the geometric limit if the run is
//! geometric, else at the impact's own time. The state differs from the
//! chattering one by the order of that speed times the chatter's duration.
//!
//! **Rebounds below the time resolution.** An impact with `0 < e < 1`
//! after which the contact leaves at the speed `w` against an acceleration
//! `a` back to its bound (the free system's, `M⁻¹(f − C v − K q)`) starts
//! rebounds of durations `2 w eᵏ/|a|`, all over within `τ∞ = 2 w/(|a|(1 −
//! e))`. When `τ∞` is at most 4 time resolutions `δ(t)` no search can
//! locate them (a tiny `e`: `event-driven(1e-20)`): the run of impacts
//! ends as an accumulation at `t + τ∞`, the contact at rest (then held if
//! pressed), as `e = 0` would leave it (docs/theory.md §9.3).
//!
//! **Rebounds below the position's resolution.** The same rebound rises
//! `w²/(2|a|)` off its bound. When that height is within the band where a
//! contact counts as at its bound (1e-12 of its length scale) its
//! rebounds cannot be told from rest: the positions that decide the next
//! landing are round-off, so the landings come at speeds set by the
//! round-off (`w ≈ √(2|a| ε)`), and they stop shrinking (a consistent-mass
//! bar nudged off its stop chattered at 3e-9 s intervals, speeds 2e-8,
//! until the event limit) or, with `e = 1`, never shrink (a landing at a
//! round-off speed where the force starts to press: 2.5e7 rebounds in 8 s).
//! The run of impacts then ends as an accumulation (for `0 < e < 1` at
//! `t + τ∞`, for `e = 1` at the impact), the contact at rest (then held if
//! pressed), the state within `w` and the band of the rebounding one. The
//! same holds for any contact an impact leaves moving off its bound that
//! low (lifted by another's impulse through the mass), and for one that an
//! accumulation's impulse lifts that low or so little that it would land
//! again before the accumulation's limit `t∞` (a joint accumulation: the
//! impulses projected again with it at rest too). The band's length
//! is the largest of the bounds and the start's displacements (every
//! dof's), or, when those are all 0, the largest displacement met at an
//! event so far.
//!
//! **Massless contact dofs** (every contact massless: mass redistribution,
//! reduced models) have no impacts: see `massless.rs`.

use super::flow::{dense, Basis, Functional, Loads, ModalFlow, Piece};
use super::record::{EventKind, EventRecord, EventsError};
use super::search::{time_resolution, AtBase, Cursor, Found, Search};
use super::Bound;
use crate::Dynamics;
use faer::Mat;
use signorini_contact::MultiProjection;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

#[path = "massless.rs"]
mod massless;

pub use massless::Condensation;

/// An impact slower than this fraction of the contact's fastest impact so
/// far ends its run of impacts as an accumulation (module docs).
const MICRO: f64 = 1e-6;

/// Events at one instant, per contact, beyond which a run makes no
/// progress in time ([`EventsError::NoProgress`]): each contact can take an
/// impact, an accumulation and a release at one instant, and the impacts
/// of others can bring it back once.
const STALL: usize = 8;

/// The most events of a run by default.
pub const MAX_EVENTS: usize = 10_000_000;

/// Contact `i` (on `dof`, between `lo` and `hi`) at the start `q0`: the
/// length its round-off is measured on, or [`EventsError::Outside`]. The
/// displacements' size at the start, and the bounds': the round-off of a
/// contact's position is the whole field's (its modes), not its own (a
/// held contact at a stop at 0 has none). A massless dof's start is the
/// static solution (module docs): not checked.
fn start_scale(i: usize, dof: usize, massless: bool, lo: f64, hi: f64, q0: &[f64]) -> Result<f64, EventsError> {
    let q = q0[dof];
    let field = q0.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let scale = [lo, hi, hi - lo, field].iter().filter(|x| x.is_finite()).fold(0.0f64, |a, x| a.max(x.abs())).max(f64::MIN_POSITIVE);
    let inside = q >= lo - 1e-12 * scale && q <= hi + 1e-12 * scale;
    if !(massless || inside) {
        return Err(EventsError::Outside { contact: i, q, lo, hi });
    }
    Ok(scale)
}

/// The load-free part of the flows of one structure: per active set met
/// (its held contacts), the modes of its free dofs — the eigen-decomposition
/// each phase's [`ModalFlow`] is made of, which no load enters. Runs of the
/// same matrices and contact dofs with other loads (another forcing
/// frequency, amplitude or phase), other bounds, restitutions or starts
/// share it ([`EventDriven::new_with`]): each active set's modes are
/// computed once, by the first run that meets it, and every run's flows
/// are the same bits as without it. Shared across threads.
pub struct FlowBases {
    m: Mat<f64>,
    k: Mat<f64>,
    c: Option<Mat<f64>>,
    /// Each contact's `(dof, massless)`.
    contacts: Vec<(usize, bool)>,
    /// Per held set (its contacts, sorted): the basis of its phase.
    map: Mutex<HashMap<Vec<usize>, Arc<Basis>>>,
}

impl FlowBases {
    /// An empty store for the structure of `dy` (its matrices and contact dofs).
    pub fn new(dy: &Dynamics) -> Self {
        Self { m: dense(&dy.mass), k: dense(&dy.stiffness), c: dy.damping.as_ref().map(dense), contacts: Self::contacts_of(dy), map: Mutex::new(HashMap::new()) }
    }

    fn contacts_of(dy: &Dynamics) -> Vec<(usize, bool)> {
        dy.contacts.iter().map(|c| (c.dof, c.massless)).collect()
    }

    /// Whether `dy` has this store's structure: the same mass, stiffness
    /// and damping, bit for bit, and the same contact dofs (its loads,
    /// bounds and restitutions may differ).
    pub fn fits(&self, dy: &Dynamics) -> bool {
        self.same(&dense(&dy.mass), &dense(&dy.stiffness), dy.damping.as_ref().map(dense).as_ref(), &Self::contacts_of(dy))
    }

    /// Whether these are this store's matrices and contacts, bit for bit.
    fn same(&self, m: &Mat<f64>, k: &Mat<f64>, c: Option<&Mat<f64>>, contacts: &[(usize, bool)]) -> bool {
        let same = |a: &Mat<f64>, b: &Mat<f64>| a.nrows() == b.nrows() && a.ncols() == b.ncols() && (0..a.nrows()).all(|i| (0..a.ncols()).all(|j| a[(i, j)].to_bits() == b[(i, j)].to_bits()));
        let damping = match (&self.c, c) {
            (None, None) => true,
            (Some(a), Some(b)) => same(a, b),
            _ => false,
        };
        damping && same(&self.m, m) && same(&self.k, k) && self.contacts == contacts
    }

    /// Active sets whose basis is stored.
    pub fn len(&self) -> usize {
        self.map.lock().map_or(0, |m| m.len())
    }

    /// Whether no basis is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The basis of the held set `key`, built by `build` if not stored
    /// (outside the lock: another thread may build it too, the same bits;
    /// the first stored is kept). An error is not stored.
    fn basis(&self, key: &[usize], build: impl FnOnce() -> Result<Basis, EventsError>) -> Result<Arc<Basis>, EventsError> {
        if let Some(b) = self.map.lock().ok().and_then(|m| m.get(key).cloned()) {
            return Ok(b);
        }
        let b = Arc::new(build()?);
        Ok(match self.map.lock() {
            Ok(mut m) => m.entry(key.to_vec()).or_insert(b).clone(),
            Err(_) => b,
        })
    }
}

thread_local! {
    /// The store [`FlowBases::lend`] lends to the runs made on this thread.
    static LENT: std::cell::RefCell<Lent> = const { std::cell::RefCell::new(Lent::None) };
    /// The flow bases the runs of this thread have built ([`bases_built`]).
    static BUILT: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many flow bases (a phase's eigen-decomposition, [`FlowBases`]'
/// unit) the event-driven runs made on this thread have built so far,
/// through a store or without one: a count a caller compares, before and
/// after its runs, with the active sets they met, to see that each was
/// built once (a test's observable, no timing).
pub fn bases_built() -> u64 {
    BUILT.with(std::cell::Cell::get)
}

impl FlowBases {
    /// Runs `f` with the store in `slot` lent to every run
    /// [`EventDriven::new`] makes on this thread meanwhile: a run of its
    /// structure ([`fits`](Self::fits)) takes its flows' bases from it and
    /// stores those it builds there; a run of another structure (or with
    /// `slot` empty) starts a new store for its own, which takes the
    /// slot's place (a run given its own store keeps it). So an integrator
    /// that a front end builds deep inside its set-up (a scene's validated
    /// run) builds through its caller's store, and the caller finds in
    /// `slot` the store of the structure built last. The same runs, bit
    /// for bit. What was lent before is lent again when `f` returns (or
    /// unwinds).
    pub fn lend<R>(slot: &mut Option<Arc<FlowBases>>, f: impl FnOnce() -> R) -> R {
        struct Restore<'a>(Lent, &'a mut Option<Arc<FlowBases>>);
        impl Drop for Restore<'_> {
            fn drop(&mut self) {
                let before = std::mem::replace(&mut self.0, Lent::None);
                let lent = LENT.with(|l| std::mem::replace(&mut *l.borrow_mut(), before));
                if let Lent::Slot(store) = lent {
                    *self.1 = store;
                }
            }
        }
        let before = LENT.with(|l| std::mem::replace(&mut *l.borrow_mut(), Lent::Slot(slot.take())));
        let _restore = Restore(before, slot);
        f()
    }
}

/// What [`FlowBases::lend`] lends: nothing, or a slot for a store.
enum Lent {
    None,
    Slot(Option<Arc<FlowBases>>),
}

/// The store lent to this thread for a run of `dy` ([`FlowBases::lend`]):
/// the slot's where it fits, else a new one put in the slot; `None` with
/// nothing lent.
fn lent_for(dy: &Dynamics) -> Option<Arc<FlowBases>> {
    LENT.with(|l| match &mut *l.borrow_mut() {
        Lent::None => None,
        Lent::Slot(slot) => Some(match slot {
            Some(b) if b.fits(dy) => b.clone(),
            _ => slot.insert(Arc::new(FlowBases::new(dy))).clone(),
        }),
    })
}

/// The basis of the held set `key` from `bases` if given, else built.
fn basis_of(bases: Option<&FlowBases>, key: &[usize], build: impl FnOnce() -> Result<Basis, EventsError>) -> Result<Arc<Basis>, EventsError> {
    let build = || {
        BUILT.with(|b| b.set(b.get() + 1));
        build()
    };
    match bases {
        Some(b) => b.basis(key, build),
        None => Ok(Arc::new(build()?)),
    }
}

struct Site {
    dof: usize,
    massless: bool,
    lo: f64,
    hi: f64,
    restitution: f64,
    /// Its length scale (for the tolerances).
    scale: f64,
    /// Its bounds and the start gave no length (all 0): the scale is the
    /// largest displacement met at an event so far.
    grows: bool,
}

/// A held contact: which, and at which bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct Hold {
    contact: usize,
    upper: bool,
}

#[derive(Clone, Copy, Debug)]
enum Watch {
    Gap { contact: usize, bound: Bound },
    Release { contact: usize },
}

/// The flow of one active set.
struct System {
    flow: ModalFlow,
    /// The free dofs, in order.
    free: Vec<usize>,
    /// `(dof, value)` of the held ones.
    held: Vec<(usize, f64)>,
    fns: Vec<Functional>,
    quiet: Vec<bool>,
    watch: Vec<Watch>,
    /// The held contacts' forces `r_a`: `(contact, r_a)`.
    forces: Vec<(usize, Functional)>,
    /// Massless dofs not held (statically condensed) and `K_SS⁻¹`.
    cond: Vec<usize>,
    g: Mat<f64>,
}

impl System {
    /// The series' loads on `piece` (flow and functionals).
    fn set_piece(&mut self, piece: &Piece) {
        self.flow.set_piece(piece);
        self.fns.iter_mut().for_each(|f| f.set_piece(piece));
        self.forces.iter_mut().for_each(|(_, f)| f.set_piece(piece));
    }
}

/// An event-driven run of a linear structure with unilateral contacts at
/// massive dofs (module docs) or at massless ones (statically condensed:
/// `massless.rs`).
pub struct EventDriven {
    n: usize,
    m: Mat<f64>,
    c: Option<Mat<f64>>,
    k: Mat<f64>,
    loads: Loads,
    /// The series' current piece (up to `piece.next`).
    piece: Piece,
    full: ModalFlow,
    sites: Vec<Site>,
    /// The contacts' Delassus matrix `M⁻¹` (massive contact dofs) or, for
    /// massless ones, `K_ZZ⁻¹` of the static condensation.
    delassus: MultiProjection,
    /// The same as built, before any solve (its statuses are a warm
    /// start): what [`restart`](Self::restart) starts from.
    delassus0: MultiProjection,
    /// The massless dofs (the massless contacts'), sorted, and `K_ZZ⁻¹`.
    zero: Vec<usize>,
    kzz_inv: Mat<f64>,
    systems: HashMap<Vec<Hold>, System>,
    holds: Vec<Hold>,
    t: f64,
    /// The modal state at `t` (read from the base: [`Self::read_at`]).
    eta: Vec<f64>,
    deta: Vec<f64>,
    /// The phase's base: the time and modal state where its flow starts (an
    /// event or a breakpoint). Every state of the phase is evaluated from
    /// it, so the sampling never re-bases the flow (docs/theory.md §9.2).
    base: (f64, Vec<f64>, Vec<f64>),
    /// Where the phase's search stands, a zero it found beyond the time
    /// asked (applied when the run gets there), and the state at it.
    cursor: Cursor,
    pending: Option<(f64, Option<usize>)>,
    /// Per functional of the phase: a gap exactly 0 at the base (a contact
    /// that the event starting the phase put on its bound, leaving it with
    /// a speed): its search takes it as 0, not as the modal state's
    /// round-off of it; or the gap of a contact released there, whose
    /// acceleration is 0 (its force's zero), not its round-off.
    base_zero: Vec<AtBase>,
    found: (Vec<f64>, Vec<f64>),
    /// Per held contact: its force's integral from the base to the last
    /// [`take_impulses`](Self::take_impulses).
    taken: Vec<f64>,
    /// `sin, cos` work storage of [`Self::read_at`].
    tr: [Vec<(f64, f64)>; 2],
    search: Search,
    events: Vec<EventRecord>,
    /// Per contact, the times of its current run of impacts (contacts
    /// chattering together each keep their own).
    streak: Vec<Vec<f64>>,
    /// Per contact, the largest impact speed so far.
    vmax: Vec<f64>,
    /// Per contact: impulses plus the held force's integral since the last
    /// [`take_impulses`](Self::take_impulses).
    impulses: Vec<f64>,
    max_events: usize,
    /// The time of the last event and the events at it.
    stall: (f64, usize),
    /// Per massive contact: its dof's row of `M⁻¹`, and that row times `K`
    /// and `C` (its free acceleration in O(n): `unresolved_rebound`).
    rebound: Vec<[Vec<f64>; 3]>,
    /// The structure's load-free bases, shared with other runs ([`FlowBases`]).
    bases: Option<Arc<FlowBases>>,
    /// Work storage of each event (`settle`): no allocation per event.
    work: Work,
    /// The free dofs' state entering a phase (`enter`'s work storage).
    entering: (Vec<f64>, Vec<f64>),
    /// The state before the located event being applied, whose modal state
    /// is the phase's (`eta`, `deta`): an impact that keeps the phase adds
    /// its changes to it ([`enter`](Self::enter)).
    pre: (Vec<f64>, Vec<f64>),
}

/// The vectors of one event's settling ([`EventDriven::settle`] and
/// `settle_static`), kept by the run and reused:
/// sized by the first events, then no event allocates (the flows of the
/// active sets are built once each and cached). Empty at the start (no
/// allocation until used).
#[derive(Default)]
struct Work {
    /// The full state at the event.
    q: Vec<f64>,
    v: Vec<f64>,
    /// Per contact: at a bound (upper?), its velocity before, held before,
    /// the LCP's bounds and multipliers, impacted.
    at: Vec<Option<bool>>,
    vbefore: Vec<f64>,
    held_before: Vec<bool>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    mu: Vec<f64>,
    impacted: Vec<bool>,
    /// Accumulations due `(contact, t∞, v_c)`, and the velocities after
    /// the impacts (a joint accumulation projects again from them).
    due: Vec<(usize, f64, f64)>,
    impacts: Vec<f64>,
    /// Contacts at rest on a bound, and the new active set.
    candidates: Vec<usize>,
    holds: Vec<Hold>,
    /// The free acceleration and jerk, a load or residual, a modal vector.
    a: Vec<f64>,
    jerk: Vec<f64>,
    f: Vec<f64>,
    y: Vec<f64>,
    piece: Piece,
    /// `settle_static`'s: the massless dofs' loads and their rates, their
    /// static positions and rates, the contacts' places among them, and
    /// which contacts their force presses on a bound.
    b: Vec<f64>,
    db: Vec<f64>,
    ys: Vec<f64>,
    dys: Vec<f64>,
    pos: Vec<usize>,
    pressed: Vec<bool>,
}

impl EventDriven {
    /// Starts at `(q0, v0)` at time `t0`, inside every contact's bounds
    /// (on a bound is allowed: an approaching contact impacts at once); a
    /// contact's restitution is its own (`Contact::restitution`) or `e`.
    pub fn new(dy: &Dynamics, t0: f64, q0: &[f64], v0: &[f64], e: f64) -> Result<Self, EventsError> {
        Self::new_with(dy, t0, q0, v0, e, None)
    }

    /// [`new`](Self::new) with the flows' bases taken from `bases` and
    /// those it builds stored there ([`FlowBases`]; ignored unless it
    /// [fits](FlowBases::fits) `dy`): the same run, bit for bit.
    /// Without one that fits: the store [lent](FlowBases::lend) to this
    /// thread, if any.
    pub fn new_with(dy: &Dynamics, t0: f64, q0: &[f64], v0: &[f64], e: f64, bases: Option<Arc<FlowBases>>) -> Result<Self, EventsError> {
        let bases = bases.filter(|b| b.fits(dy)).or_else(|| lent_for(dy));
        let n = dy.n();
        let loads = Loads::of(dy)?;
        let mut sites = Vec::new();
        for (i, c) in dy.contacts.iter().enumerate() {
            let restitution = c.restitution.unwrap_or(e);
            if !(0.0..=1.0).contains(&restitution) {
                return Err(EventsError::Restitution { contact: i, restitution });
            }
            if c.massless && restitution != 0.0 {
                return Err(EventsError::MasslessRestitution { contact: i, restitution });
            }
            let (lo, hi) = (c.bounds.lo, c.bounds.hi);
            let scale = start_scale(i, c.dof, c.massless, lo, hi, q0)?;
            sites.push(Site { dof: c.dof, massless: c.massless, lo, hi, restitution, scale, grows: scale == f64::MIN_POSITIVE });
        }
        let (m, k, c) = (dense(&dy.mass), dense(&dy.stiffness), dy.damping.as_ref().map(dense));
        let mut zero: Vec<usize> = dy.contacts.iter().filter(|c| c.massless).map(|c| c.dof).collect();
        zero.sort_unstable();
        zero.dedup();
        // As `Dynamics::validate` requires (checked here too: this is a
        // library entry point): one mass treatment for all contacts, and a
        // massless dof's row of M zero.
        if !zero.is_empty() {
            if let Some(i) = dy.contacts.iter().position(|c| !c.massless) {
                return Err(EventsError::Contacts(format!("contacts[{i}] is massive and another is massless: every contact must be massless, or every one massive")));
            }
            if let Some(&d) = zero.iter().find(|&&d| (0..n).any(|j| m[(d, j)] != 0.0)) {
                return Err(EventsError::Contacts(format!("the massless contact dof {d} has a nonzero row of M")));
            }
            // Nor of C: the node has no velocity of its own (its equation
            // would not be static; docs/theory.md §9.3).
            if let Some(d) = c.as_ref().and_then(|c| zero.iter().copied().find(|&d| (0..n).any(|j| c[(d, j)] != 0.0))) {
                return Err(EventsError::Contacts(format!("the massless contact dof {d} has a nonzero row of C (the damping matrix): a massless node has no velocity of its own")));
            }
        }
        let (full, delassus, kzz_inv) = if zero.is_empty() {
            // The active set without a held contact: the same matrices as the full problem's.
            let basis = basis_of(bases.as_deref(), &[], || Basis::new(m.clone(), k.clone(), c.clone()))?;
            let full = ModalFlow::with_loads(&basis, &loads);
            let dofs: Vec<usize> = sites.iter().map(|s| s.dof).collect();
            let columns = dofs.iter().map(|&d| full.minv_column(d)).collect();
            let delassus = MultiProjection::new(dofs, columns)?;
            (full, delassus, Mat::zeros(0, 0))
        } else {
            let none = Loads { constant: Vec::new(), waves: Vec::new(), ramps: Vec::new() };
            let full = ModalFlow::from_parts(Mat::zeros(0, 0), Mat::zeros(0, 0), None, &none)?;
            let (delassus, kzz_inv) = massless::static_delassus(&k, &zero, &sites)?;
            (full, delassus, kzz_inv)
        };
        let k_contacts = sites.len();
        let rebound = if zero.is_empty() { sites.iter().map(|s| rebound_rows(&full, &k, c.as_ref(), s.dof)).collect() } else { Vec::new() };
        // The structure, built once; the run's state (its time, phase,
        // search, events and impulses) is placed by `restart`, so that a
        // new run and a restarted one cannot start differently.
        let mut r = Self {
            n,
            m,
            c,
            k,
            loads,
            piece: Piece::default(),
            full,
            sites,
            delassus0: delassus.clone(),
            delassus,
            zero,
            kzz_inv,
            systems: HashMap::new(),
            holds: Vec::new(),
            t: t0,
            eta: Vec::new(),
            deta: Vec::new(),
            base: (t0, Vec::new(), Vec::new()),
            cursor: Cursor { tau: 0.0, window: 1.0 },
            pending: None,
            base_zero: Vec::new(),
            found: (Vec::new(), Vec::new()),
            taken: vec![0.0; k_contacts],
            tr: [Vec::new(), Vec::new()],
            search: Search::new(n),
            events: Vec::new(),
            streak: vec![Vec::new(); k_contacts],
            vmax: vec![0.0; k_contacts],
            impulses: vec![0.0; k_contacts],
            max_events: MAX_EVENTS,
            stall: (f64::NAN, 0),
            rebound,
            bases,
            work: Work::default(),
            entering: (Vec::new(), Vec::new()),
            pre: (Vec::new(), Vec::new()),
        };
        r.restart(t0, q0, v0)?;
        Ok(r)
    }

    /// The most events of the run ([`MAX_EVENTS`] by default) for the
    /// sampled runs of [`super::EventStepper`].
    pub fn with_max_events(mut self, max_events: usize) -> Self {
        self.max_events = max_events;
        self
    }

    /// [`with_max_events`](Self::with_max_events) in place.
    pub fn set_max_events(&mut self, max_events: usize) {
        self.max_events = max_events;
    }

    /// Starts the run again at `(q0, v0)` at `t0`, on the same structure
    /// and loads: the same run as [`new`](Self::new) with these arguments
    /// would make (the same errors, the same events and states, bit for
    /// bit), without building again the flow of each active set met so far
    /// (their modes and functionals are kept: they depend on the structure
    /// and loads only). The event limit and the interrupt stay as set.
    /// After an error the run must be started again before it is used.
    pub fn restart(&mut self, t0: f64, q0: &[f64], v0: &[f64]) -> Result<(), EventsError> {
        // [`new`](Self::new) starts through here. The contacts placed (their
        // restitutions were checked by `new`, which placed them first: its
        // errors in their order).
        for (i, s) in self.sites.iter_mut().enumerate() {
            let scale = start_scale(i, s.dof, s.massless, s.lo, s.hi, q0)?;
            (s.scale, s.grows) = (scale, scale == f64::MIN_POSITIVE);
        }
        self.delassus.clone_from(&self.delassus0);
        self.piece = Piece::default();
        self.holds.clear();
        self.t = t0;
        self.eta.clear();
        self.deta.clear();
        self.base.0 = t0;
        self.base.1.clear();
        self.base.2.clear();
        self.cursor = Cursor { tau: 0.0, window: 1.0 };
        self.pending = None;
        self.base_zero.clear();
        self.found.0.clear();
        self.found.1.clear();
        self.taken.iter_mut().for_each(|x| *x = 0.0);
        let (interrupt, at_pause) = (self.search.interrupt.take(), self.search.take_at_pause);
        self.search = Search::new(self.n);
        self.search.interrupt = interrupt;
        self.search.take_at_pause = at_pause;
        self.events.clear();
        self.streak.iter_mut().for_each(Vec::clear);
        self.vmax.iter_mut().for_each(|x| *x = 0.0);
        self.impulses.iter_mut().for_each(|x| *x = 0.0);
        self.stall = (f64::NAN, 0);
        let (q, v) = self.work_state(q0, v0);
        self.settle(t0, q, v, None)
    }

    /// Runs to `t_end` exactly; more than `max_events` events logged on
    /// the way (records, as [`events`](Self::events) lists them and the
    /// run's own limit counts them: impacts of several contacts at one
    /// instant count one each) stop it with [`EventsError::TooManyEvents`]
    /// (the state is then the one after the last event taken, the events
    /// so far kept).
    pub fn run_until(&mut self, t_end: f64, max_events: usize) -> Result<(), EventsError> {
        let start = self.events.len();
        while self.next_event(t_end)?.is_some() {
            let taken = self.events.len() - start;
            if taken > max_events {
                return Err(EventsError::TooManyEvents { t: self.t, events: taken });
            }
        }
        Ok(())
    }

    /// Runs to `t_end`, counting against the run's `max_events` (all
    /// events since the start).
    pub(crate) fn advance_to(&mut self, t_end: f64) -> Result<(), EventsError> {
        while self.next_event(t_end)?.is_some() {
            if self.events.len() > self.max_events {
                return Err(EventsError::TooManyEvents { t: self.t, events: self.events.len() });
            }
        }
        Ok(())
    }

    /// Advances to the next event that logs a record, applies it and
    /// returns it (the located one; simultaneous impacts of other contacts
    /// are logged too), or to `t_end` if none comes before (then `None`).
    /// An event that logs nothing (a contact landing at zero speed: no
    /// impact, docs/theory.md §9.3) is applied and the run goes on: `None`
    /// always means the run stands at `t_end`. A run of events that makes
    /// no progress in time (more than 8 events per contact at one instant,
    /// logged or not) stops with [`EventsError::NoProgress`] at once.
    pub fn next_event(&mut self, t_end: f64) -> Result<Option<EventRecord>, EventsError> {
        loop {
            match self.next_change(t_end)? {
                Reached::End => return Ok(None),
                Reached::Event(Some(e)) => return Ok(Some(e)),
                Reached::Event(None) => {}
            }
        }
    }

    /// [`next_event`](Self::next_event) one applied event at a time,
    /// those that log nothing included (where the active set may change
    /// without a record: a caller that follows the phases, as the orbits'
    /// linearisation does, sees each).
    pub fn next_change(&mut self, t_end: f64) -> Result<Reached, EventsError> {
        let reached = self.next_event_unchecked(t_end)?;
        if let Reached::Event(e) = &reached {
            let t = e.map_or(self.t, |e| e.t);
            if t == self.stall.0 {
                self.stall.1 += 1;
                if self.stall.1 > STALL * (self.sites.len() + 1) {
                    let recent = self.events.len().saturating_sub(6);
                    let kinds: Vec<String> = self.events[recent..].iter().map(|e| format!("{} of contact {}", e.kind.name(), e.contact)).collect();
                    return Err(EventsError::NoProgress { t, events: self.stall.1, cycle: kinds.join(", ") });
                }
            } else {
                self.stall = (t, 1);
            }
        }
        Ok(reached)
    }

    fn next_event_unchecked(&mut self, t_end: f64) -> Result<Reached, EventsError> {
        loop {
            if t_end <= self.t {
                return Ok(Reached::End);
            }
            if let Some((te, which)) = self.pending {
                // An event at `t_end` itself waits for the next call unless
                // events at the pause are taken: the search's rule for a
                // zero at a step's start, here for one located inside a
                // step that ends there (docs/theory.md §9.4).
                if self.search.beyond_pause(te, t_end) && (te > t_end || which.is_some()) {
                    // Beyond the time asked: the state there, read from the base.
                    self.read_at(t_end);
                    return Ok(Reached::End);
                }
                self.pending = None;
                match which {
                    Some(which) => return Ok(Reached::Event(self.apply(te, which)?)),
                    None => self.next_piece(te),
                }
                continue;
            }
            // The phase's search goes on from where it stands, whatever
            // `t_end` is: it only pauses there (docs/theory.md §9.2).
            let sys = &self.systems[&self.holds];
            let base = (self.base.0, &self.base.1[..], &self.base.2[..]);
            let state = (&mut self.found.0[..], &mut self.found.1[..]);
            match self.search.resume(&sys.flow, base, &mut self.cursor, state, (&sys.fns, &sys.quiet, &self.base_zero), self.piece.next, t_end)? {
                Found::Event(te, which) => self.pending = Some((te, Some(which))),
                // A breakpoint of the series (the state there in `found`).
                Found::End => self.pending = Some((self.piece.next, None)),
                Found::Paused => {
                    self.read_at(t_end);
                    return Ok(Reached::End);
                }
            }
        }
    }

    /// The series' next piece from its breakpoint `tp` (the state there in
    /// `found`): a new phase with the piece's loads.
    fn next_piece(&mut self, tp: f64) {
        self.close_phase(tp);
        self.t = tp;
        self.eta.clone_from(&self.found.0);
        self.deta.clone_from(&self.found.1);
        self.loads.piece_into(tp, &mut self.piece);
        let sys = self.systems.get_mut(&self.holds).expect("the current phase's system");
        sys.set_piece(&self.piece);
        self.start_phase();
    }

    /// Applies the event `which` found at `t` (its state in `found`).
    fn apply(&mut self, t: f64, which: usize) -> Result<Option<EventRecord>, EventsError> {
        self.close_phase(t);
        self.t = t;
        self.eta.clone_from(&self.found.0);
        self.deta.clone_from(&self.found.1);
        let watch = self.systems[&self.holds].watch[which];
        let (q, v) = self.physical_work();
        // An event inside an accumulation's tail [t_k, t∞] ends it: the
        // run has held that contact at rest since t_k, and this event's
        // impulses (or release) are not the tail the limit extrapolated;
        // its row takes this time (docs/theory.md §9.3, "An event inside
        // an accumulation's tail"). Only the last instant's accumulations
        // can lie beyond `t`.
        for r in self.events.iter_mut().rev().take_while(|r| r.t > t) {
            if r.kind == EventKind::Accumulation {
                r.t = t;
            }
        }
        let before = self.events.len();
        match watch {
            Watch::Gap { contact, bound } => self.settle(t, q, v, Some((contact, bound)))?,
            Watch::Release { contact } => {
                let mut rest = std::mem::take(&mut self.work.holds);
                rest.clear();
                rest.extend_from_slice(&self.holds);
                let mut entered = Ok(());
                let mut next = Some(contact);
                // Every held contact whose force reaches 0 within the time
                // resolution of this release leaves with it, from this
                // state: taken one by one, the first left with a velocity
                // of round-off (1e-32) that read as an approach once the
                // second left, landed, and both were held and released
                // again at one instant until `NoProgress` (two equal
                // masses under one load: docs/theory.md §9.3).
                while let Some(c) = next {
                    self.streak[c].clear();
                    self.events.push(EventRecord { t, kind: EventKind::Release, contact: c, velocity_before: 0.0, velocity_after: 0.0, impulse: 0.0 });
                    rest.retain(|h| h.contact != c);
                    entered = self.enter(&mut rest, &q, &v, t, false);
                    next = if entered.is_ok() && !rest.is_empty() { self.release_within(t) } else { None };
                }
                (self.work.holds, self.work.q, self.work.v) = (rest, q, v);
                entered?;
            }
        }
        Ok(self.events.get(before).copied())
    }

    /// The held contact whose force the phase just entered at `t` finds at
    /// its zero within `4 δ(t)` (§9.2's resolution), if any: the search
    /// looks ahead from the base without moving the phase's cursor.
    fn release_within(&mut self, t: f64) -> Option<usize> {
        let sys = &self.systems[&self.holds];
        let mut cursor = Cursor::start(&sys.flow);
        let base = (self.base.0, &self.base.1[..], &self.base.2[..]);
        let state = (&mut self.found.0[..], &mut self.found.1[..]);
        let end = (t + 4.0 * time_resolution(t)).min(self.piece.next);
        match self.search.resume(&sys.flow, base, &mut cursor, state, (&sys.fns, &sys.quiet, &self.base_zero), end, f64::INFINITY) {
            Ok(Found::Event(_, which)) => match sys.watch[which] {
                Watch::Release { contact } => Some(contact),
                Watch::Gap { .. } => None,
            },
            _ => None,
        }
    }

    /// The state at `t` in the current phase, read from its base (no
    /// re-basing: a sample never changes the trajectory).
    fn read_at(&mut self, t: f64) {
        let sys = &self.systems[&self.holds];
        self.t = t;
        self.eta.clone_from(&self.base.1);
        self.deta.clone_from(&self.base.2);
        if t != self.base.0 {
            sys.flow.advance_modal(self.base.0, &mut self.eta, &mut self.deta, t - self.base.0, &mut self.tr);
        }
    }

    /// The held forces' integrals from the base to `t` (the state there
    /// in `found`), less what was taken, into the impulses: the phase ends.
    fn close_phase(&mut self, t: f64) {
        let sys = &self.systems[&self.holds];
        let base = (&self.base.1[..], &self.base.2[..]);
        for (contact, r) in &sys.forces {
            let i = r.integral(&sys.flow, self.base.0, base, (&self.found.0, &self.found.1), t - self.base.0, &mut self.tr);
            self.impulses[*contact] += i - self.taken[*contact];
            self.taken[*contact] = 0.0;
        }
    }

    /// A phase starts at `t` from the state `eta`, `deta`: its base, its
    /// search's first window.
    fn start_phase(&mut self) {
        let flow = &self.systems[&self.holds].flow;
        self.base.0 = self.t;
        self.base.1.clone_from(&self.eta);
        self.base.2.clone_from(&self.deta);
        self.cursor = Cursor::start(flow);
        self.pending = None;
        self.base_zero.clear();
        self.base_zero.resize(self.systems[&self.holds].fns.len(), AtBase::Open);
        self.taken.iter_mut().for_each(|x| *x = 0.0);
        self.found.0.resize(self.eta.len(), 0.0);
        self.found.1.resize(self.eta.len(), 0.0);
    }

    /// [`physical`](Self::physical) in the work storage's vectors, taken
    /// out of it (a caller puts them back: no allocation per event).
    fn physical_work(&mut self) -> (Vec<f64>, Vec<f64>) {
        let (mut q, mut v) = (std::mem::take(&mut self.work.q), std::mem::take(&mut self.work.v));
        for x in [&mut q, &mut v] {
            x.clear();
            x.resize(self.n, 0.0);
        }
        self.state_into(&mut q, &mut v);
        (q, v)
    }

    /// `(q, v)` copied into the work storage's vectors, taken out of it
    /// (a caller puts them back).
    fn work_state(&mut self, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (mut wq, mut wv) = (std::mem::take(&mut self.work.q), std::mem::take(&mut self.work.v));
        wq.clear();
        wq.extend_from_slice(q);
        wv.clear();
        wv.extend_from_slice(v);
        (wq, wv)
    }

    /// The full state of the current phase.
    fn physical(&self) -> (Vec<f64>, Vec<f64>) {
        let (mut q, mut v) = (vec![0.0; self.n], vec![0.0; self.n]);
        self.state_into(&mut q, &mut v);
        (q, v)
    }

    /// The state `(q, v)` now, into `q` and `v` (no allocation).
    ///
    /// # Panics
    /// If a slice's length is not the problem's (a programmer error).
    #[track_caller]
    pub fn state_into(&self, q: &mut [f64], v: &mut [f64]) {
        assert!(q.len() == self.n && v.len() == self.n, "state slices of {} entries", self.n);
        let sys = &self.systems[&self.holds];
        sys.flow.physical_into(self.t, &self.eta, &self.deta, &sys.free, q, v);
        for &(d, x) in &sys.held {
            (q[d], v[d]) = (x, 0.0);
        }
        if !sys.cond.is_empty() {
            self.condensed_into(sys, q, v);
        }
    }

    /// The impacts, accumulation and new active set at time `t` from the
    /// state `(q, v)`; `primary` is the located event's contact.
    /// The vectors `q`, `v` (the work storage's, taken out of it) are put
    /// back there, with the rest of the work storage (no allocation per
    /// event).
    fn settle(&mut self, t: f64, mut q: Vec<f64>, mut v: Vec<f64>, primary: Option<(usize, Bound)>) -> Result<(), EventsError> {
        // A contact whose bounds and start are all 0 has no length of its
        // own (its band was exact equality: two stops reached together at
        // 0 were located 1e-16 apart and taken one by one); it takes the
        // largest displacement met at an event so far (the first ones may
        // be round-off: a bar squeezed between stops at 0 met 1e-26 first).
        let qmax = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for s in self.sites.iter_mut().filter(|s| s.grows) {
            s.scale = s.scale.max(qmax);
        }
        let mut w = std::mem::take(&mut self.work);
        let settled = if self.zero.is_empty() { self.settle_massive(t, &mut q, &mut v, primary, &mut w) } else { self.settle_static(t, &mut q, &mut v, primary, &mut w) };
        (w.q, w.v) = (q, v);
        self.work = w;
        settled
    }

    /// [`settle`](Self::settle) with contacts at massive dofs (`w`: the
    /// work storage).
    fn settle_massive(&mut self, t: f64, q: &mut [f64], v: &mut [f64], primary: Option<(usize, Bound)>, w: &mut Work) -> Result<(), EventsError> {
        // A located event: the modal state (`eta`, `deta`) is the phase's
        // at `t`, of this state (`enter` adds the event's changes to it).
        let located = primary.is_some();
        if located {
            self.pre.0.clear();
            self.pre.0.extend_from_slice(q);
            self.pre.1.clear();
            self.pre.1.extend_from_slice(v);
        }
        let kc = self.sites.len();
        // Which contacts are at a bound (side: upper?).
        let at = &mut w.at;
        at.clear();
        at.resize(kc, None);
        for (j, s) in self.sites.iter().enumerate() {
            let qc = q[s.dof];
            let tol = 1e-12 * s.scale;
            at[j] = if let Some(h) = self.holds.iter().find(|h| h.contact == j) {
                Some(h.upper)
            } else if let Some((_, b)) = primary.filter(|p| p.0 == j) {
                Some(b == Bound::Upper)
            } else if self.at_release(j, t) {
                // Leaving: no impact, no hold (another contact's event a
                // few ulps after this one's release landed it at a speed
                // of round-off and released it again).
                None
            } else if qc - s.lo <= tol {
                Some(false)
            } else if s.hi - qc <= tol {
                Some(true)
            } else {
                None
            };
            if let Some(up) = at[j] {
                q[s.dof] = if up { s.hi } else { s.lo };
            }
        }
        // The located contact arrives: a speed away from its bound is the
        // round-off that the search read as zero (it locates a zero only
        // when the first derivative beyond round-off points into the
        // bound), so it is at rest there (docs/theory.md §9.3).
        if let Some((j, b)) = primary {
            let dof = self.sites[j].dof;
            if (b == Bound::Upper && v[dof] < 0.0) || (b == Bound::Lower && v[dof] > 0.0) {
                v[dof] = 0.0;
            }
        }
        // Newton's law for all of them at once: the velocity LCP.
        let vbefore = &mut w.vbefore;
        vbefore.clear();
        vbefore.extend(self.sites.iter().map(|s| v[s.dof]));
        let held_before = &mut w.held_before;
        held_before.clear();
        held_before.extend((0..kc).map(|j| self.holds.iter().any(|h| h.contact == j)));
        let (lo, hi) = (&mut w.lo, &mut w.hi);
        unbounded(lo, hi, kc);
        for j in 0..kc {
            let e = self.sites[j].restitution;
            match at[j] {
                // Equal bounds: a bilateral constraint stops the dof.
                Some(_) if self.sites[j].lo == self.sites[j].hi => (lo[j], hi[j]) = (0.0, 0.0),
                Some(false) => lo[j] = (-e * vbefore[j]).max(0.0),
                Some(true) => hi[j] = (-e * vbefore[j]).min(0.0),
                None => {}
            }
        }
        self.delassus.project(v, lo, hi)?;
        let mu = &mut w.mu;
        mu.clear();
        mu.extend_from_slice(self.delassus.multipliers());
        // The impacts: every contact the LCP gives an impulse, and the
        // located one when it arrives with a speed (a landing at zero speed
        // without impulse is no impact: docs/theory.md §9.3).
        let impacted = &mut w.impacted;
        impacted.clear();
        impacted.resize(kc, false);
        for j in 0..kc {
            let located = primary.is_some_and(|p| p.0 == j);
            if at[j].is_some() && (mu[j] != 0.0 || (located && vbefore[j] != 0.0)) {
                impacted[j] = true;
                self.impulses[j] += mu[j];
                self.events.push(EventRecord { t, kind: EventKind::Impact, contact: j, velocity_before: vbefore[j], velocity_after: v[self.sites[j].dof], impulse: mu[j] });
            }
        }
        // Accumulation, per contact: each contact's run of impacts (two
        // contacts chattering together each have theirs), and micro-impacts
        // (module docs), end with the contact at rest.
        // The accumulations' rows start here, in time order, at or after `t`.
        let tail_rows = self.events.len();
        let due = &mut w.due;
        due.clear();
        for j in 0..kc {
            if held_before[j] {
                self.streak[j].clear();
            }
            if !impacted[j] || held_before[j] {
                continue;
            }
            let speed = vbefore[j].abs();
            let micro = speed <= MICRO * self.vmax[j];
            self.vmax[j] = self.vmax[j].max(speed);
            self.streak[j].push(t);
            let e = self.sites[j].restitution;
            let unresolved = || self.unresolved_rebound(t, q, v, j, at[j] == Some(true));
            if e > 0.0 && e < 1.0 {
                let streak = &self.streak[j];
                let geometric = accumulation(streak);
                let close = geometric.filter(|g| g.1 <= 1e-9 * t.abs().max(streak[streak.len() - 1] - streak[0])).map(|g| g.0);
                if let Some(t_inf) = close.or(micro.then(|| geometric.map_or(t, |g| g.0))).or_else(unresolved) {
                    due.push((j, t_inf, v[self.sites[j].dof]));
                }
            } else if e == 1.0 {
                if let Some(t_inf) = unresolved() {
                    due.push((j, t_inf, v[self.sites[j].dof]));
                }
            }
        }
        // Any other contact on its bound that leaves it too low to be told
        // from rest (lifted by another contact's impulse through the mass,
        // held before or not): at rest as well. Two contacts coupled so
        // that each one's plastic impact lifts the other landed in turn,
        // 1/15 as fast each time, down to heights of 3e-18 and no lower,
        // at 5e-9 s intervals, until the event limit.
        for j in 0..kc {
            if at[j].is_none() || due.iter().any(|d| d.0 == j) {
                continue;
            }
            if let Some(t_inf) = self.lifted_to_rest(t, q, v, j, at[j] == Some(true), 0.0) {
                due.push((j, t_inf, v[self.sites[j].dof]));
            }
        }
        if !due.is_empty() {
            // At rest on their bounds (lo = hi = 0: an equality), the
            // others at their bounds not pushed through.
            for i in 0..kc {
                match at[i] {
                    Some(false) => lo[i] = 0.0,
                    Some(true) => hi[i] = 0.0,
                    None => {}
                }
            }
            // The accumulations' impulses lift the other contacts on their
            // bounds through a consistent mass (they stand for the smooth
            // forces over the tail [t, t∞], during which those stay on):
            // one lifted within the band, or landing again before the
            // latest t∞, is at rest too (a joint accumulation), the
            // impulses projected again from the impacts' velocities. Two
            // contacts whose accumulations lifted each other landed in turn
            // at 1e-10 and 1e-8 m/s to the event limit, or before the
            // other's logged t∞ (docs/theory.md §9.3).
            let impacts = &mut w.impacts;
            impacts.clear();
            impacts.extend_from_slice(v);
            loop {
                for &(j, ..) in due.iter() {
                    (lo[j], hi[j]) = (0.0, 0.0);
                }
                self.delassus.project(v, lo, hi)?;
                let joined = due.len();
                let tail = due.iter().fold(t, |m, d| m.max(d.1)) - t;
                for j in 0..kc {
                    if at[j].is_some() && !due.iter().any(|d| d.0 == j) {
                        if let Some(t_inf) = self.lifted_to_rest(t, q, v, j, at[j] == Some(true), tail) {
                            due.push((j, t_inf, v[self.sites[j].dof]));
                        }
                    }
                }
                if due.len() == joined {
                    mu.clear();
                    mu.extend_from_slice(self.delassus.multipliers());
                    break;
                }
                v.copy_from_slice(impacts);
            }
            for (i, m) in mu.iter().enumerate() {
                self.impulses[i] += m;
            }
            // Logged in time order.
            due.sort_by(|a, b| a.1.total_cmp(&b.1));
            for &(j, t_inf, vb) in due.iter() {
                self.events.push(EventRecord { t: t_inf, kind: EventKind::Accumulation, contact: j, velocity_before: vb, velocity_after: v[self.sites[j].dof], impulse: mu[j] });
                self.streak[j].clear();
            }
        }
        // The new active set: contacts at rest on their bound that the
        // acceleration LCP presses against it.
        let vscale = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let candidates = &mut w.candidates;
        candidates.clear();
        candidates.extend((0..kc).filter(|&j| at[j].is_some() && v[self.sites[j].dof].abs() <= 1e-13 * vscale.max(f64::MIN_POSITIVE)));
        let holds = &mut w.holds;
        holds.clear();
        if !candidates.is_empty() {
            for &j in candidates.iter() {
                v[self.sites[j].dof] = 0.0;
            }
            let a = &mut w.a;
            self.free_acceleration(t, q, v, (&mut w.f, &mut w.y, a));
            let ascale = a.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(f64::MIN_POSITIVE);
            unbounded(lo, hi, kc);
            for &j in candidates.iter() {
                if self.sites[j].lo == self.sites[j].hi {
                    (lo[j], hi[j]) = (0.0, 0.0);
                } else if at[j] == Some(true) {
                    hi[j] = 0.0;
                } else {
                    lo[j] = 0.0;
                }
            }
            self.delassus.project(a, lo, hi)?;
            let r = self.delassus.multipliers();
            // The search's rule for a zero (docs/theory.md §9.2, "Zeros at
            // the time resolution"): an acceleration that the jerk moves by
            // more than itself within the time resolution does not decide;
            // the contact stays held, and its force's rate decides.
            let jerk = &mut w.jerk;
            self.free_jerk(t, v, a, &mut w.piece, (&mut w.f, &mut w.y, jerk));
            // The search's resolution (relative to the phase without time-dependent loads).
            let dt_res = 4.0 * time_resolution(if self.loads.time_dependent() { t } else { t - self.base.0 });
            for &j in candidates.iter() {
                let (bilateral, dof) = (self.sites[j].lo == self.sites[j].hi, self.sites[j].dof);
                let leaving = !bilateral && r[j] == 0.0 && a[dof].abs() > 1e-12 * ascale + jerk[dof].abs() * dt_res;
                if !leaving {
                    holds.push(Hold { contact: j, upper: at[j] == Some(true) });
                }
            }
        }
        for h in holds.iter() {
            self.streak[h.contact].clear();
        }
        // On an error (an active set without an exact flow) the state stays
        // the one before the event, whole.
        self.enter(holds, q, v, t, located)?;
        // A held contact the event lets go (the acceleration LCP gives it
        // no force, or an impulse lifts it) is released at `t`. Its row
        // goes after this instant's rows and before the accumulations'
        // rows logged at a later limit `t∞`: the held phase starts at `t`,
        // and a row after them broke the time order (docs/theory.md §9.3).
        // Logged once the phase is entered: its force jumped, so its gap
        // does not leave from a force's zero (`at_release`).
        let first = tail_rows + self.events[tail_rows..].partition_point(|r| r.t <= t);
        let held = &self.holds;
        let let_go = (0..kc).filter(|&j| w.held_before[j] && !held.iter().any(|h| h.contact == j));
        for (at_row, j) in (first..).zip(let_go) {
            self.events.insert(at_row, EventRecord { t, kind: EventKind::Release, contact: j, velocity_before: 0.0, velocity_after: v[self.sites[j].dof], impulse: 0.0 });
        }
        self.t = t;
        Ok(())
    }

    /// The limit `t + τ∞` of contact `j`'s rebounds after an impact at `t`
    /// if they cannot be resolved (module docs): leaving its bound at the
    /// speed `w` against an acceleration `a` back to it, they take
    /// `τ∞ = 2 w / (|a| (1 − e))`, here at most `4 δ(t)`, or rise
    /// `w²/(2|a|)`, here within the band where the contact counts as at its
    /// bound (`settle`'s); with `e = 1` (no limit) `t` itself.
    fn unresolved_rebound(&self, t: f64, q: &[f64], v: &[f64], j: usize, upper: bool) -> Option<f64> {
        let (w, a) = self.departure(t, q, v, j, upper)?;
        let tau = self.rebounds_last(w, a, j);
        // With `e = 1` each rebound lasts `2w/|a|` and none is shorter: a
        // free mass pushed onto its stop (no stiffness, no length: the
        // position band is 0) rebounded every 2e-17 s from `v₀ = 1e-17`
        // until the event limit (docs/theory.md §9.3).
        let flight = if self.sites[j].restitution < 1.0 { tau } else { 2.0 * w / a };
        let below_time = flight <= 4.0 * time_resolution(t);
        let below_position = w * w / (2.0 * a) <= self.rest_band(j, a);
        (below_time || below_position).then_some(t + tau)
    }

    /// The band within which contact `j`, pulled back by the acceleration
    /// `a`, counts as at its bound: 1e-12 of its length scale. A contact
    /// with no length yet (`grows`: bounds and start all 0) also counts as
    /// at rest within the round-off `ε` of its dof's own static deflection
    /// under `a`, `a / (M⁻¹K)ⱼⱼ` (`|f|/k` for one dof): else its scale
    /// stays at the zero-speed landings' 0, and an elastic rebound of 5e-35
    /// under a unit push (`x'' + x = −1` from 0 at `v₀ = 1e-17`) chattered
    /// every 2e-17 s until the event limit. Only `ε` of it: rebounds of
    /// 5e-13 there are resolved to 1e-12 (`events_driven.rs`' chatter).
    fn rest_band(&self, j: usize, a: f64) -> f64 {
        let s = &self.sites[j];
        let stiffness = self.rebound.get(j).map_or(0.0, |r| r[1][s.dof].abs());
        let own = if s.grows && stiffness > 0.0 { a / stiffness } else { 0.0 };
        (1e-12 * s.scale).max(f64::EPSILON * own)
    }

    /// Contact `j` on its bound (its upper one if `upper`) leaving it at a
    /// speed `w` against the acceleration `a` back: taken at rest if its
    /// rise `w²/(2|a|)` is within the band where it counts as at its bound,
    /// or if it would land again within `tail` (`2w/|a| <= tail`: inside
    /// an accumulation's neglected tail); then the limit `t + τ∞` of its
    /// rebounds (module docs), where it is logged.
    fn lifted_to_rest(&self, t: f64, q: &[f64], v: &[f64], j: usize, upper: bool, tail: f64) -> Option<f64> {
        let (w, a) = self.departure(t, q, v, j, upper).filter(|&(w, a)| w * w / (2.0 * a) <= self.rest_band(j, a) || 2.0 * w / a <= tail)?;
        Some(t + self.rebounds_last(w, a, j))
    }

    /// How long contact `j`'s rebounds last, leaving at the speed `w`
    /// against the acceleration `a`: `τ∞ = 2 w / (a (1 − e))`; 0 for
    /// `e = 1` (they have no end; taken at rest at once).
    fn rebounds_last(&self, w: f64, a: f64, j: usize) -> f64 {
        let e = self.sites[j].restitution;
        if e < 1.0 {
            2.0 * w / (a * (1.0 - e))
        } else {
            0.0
        }
    }

    /// Contact `j` leaving its bound (its upper one if `upper`): its speed
    /// away `w > 0` and the free acceleration's size `a > 0` that brings
    /// it back, if it does.
    fn departure(&self, t: f64, q: &[f64], v: &[f64], j: usize, upper: bool) -> Option<(f64, f64)> {
        let (s, sign) = (&self.sites[j], if upper { -1.0 } else { 1.0 });
        let w = sign * v[s.dof];
        if !(w > 0.0) {
            return None;
        }
        // The row of M⁻¹(f(t) − K q − C v) at the contact dof.
        let [m, km, cm] = &self.rebound[j];
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
        let mut f = dot(m, &self.loads.constant);
        for (g, amp, w, p) in &self.loads.waves {
            f += dot(m, g) * amp * (w * t + p).sin();
        }
        for (h, series, _) in &self.loads.ramps {
            f += dot(m, h) * series.value(t);
        }
        let a = sign * (f - dot(km, q) - dot(cm, v));
        (a < 0.0).then_some((w, -a))
    }

    /// `M⁻¹ (f(t) − C v − K q)` into `out` (`f`, `y`: work storage).
    fn free_acceleration(&self, t: f64, q: &[f64], v: &[f64], (f, y, out): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>)) {
        f.clear();
        f.extend((0..self.n).map(|r| self.loads.value(r, t)));
        self.minv_residual(f, q, v, y, out);
    }

    /// `M⁻¹ (f − K x − C y)` into `out` (`f` overwritten; `work`: work storage).
    fn minv_residual(&self, f: &mut [f64], x: &[f64], y: &[f64], work: &mut Vec<f64>, out: &mut Vec<f64>) {
        for (r, fr) in f.iter_mut().enumerate() {
            for s in 0..self.n {
                *fr -= self.k[(r, s)] * x[s] + self.c.as_ref().map_or(0.0, |c| c[(r, s)] * y[s]);
            }
        }
        self.full.minv_into(f, work, out);
    }

    /// `M⁻¹ (f'(t) − C a − K v)` into `out`: the jerk of the free system (a
    /// scale for the hold decision's round-off, not a phase's exact jerk;
    /// `piece`, `f`, `y`: work storage).
    fn free_jerk(&self, t: f64, v: &[f64], a: &[f64], piece: &mut Piece, (f, y, out): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>)) {
        self.loads.piece_into(t, piece);
        f.clear();
        f.extend((0..self.n).map(|r| self.loads.rate(r, t, piece)));
        self.minv_residual(f, v, a, y, out);
    }

    /// Switches to the phase of `holds` from the full state at `t` (its
    /// flow built first: on an error nothing changes). After a located
    /// event (`jump`: `eta, deta` the phase's state at `t`, of the state
    /// `pre`) that keeps the phase, the modal state goes on with the
    /// event's changes added (`Φᵀ M (q − q⁻, v − v⁻)`: the velocity jump,
    /// the contacts placed on their bounds), not re-made from `(q, v)`:
    /// the round trip `Φ Φᵀ M` of the whole state, the identity but for the
    /// basis' round-off, drifted the energy by a fixed fraction of ε per
    /// event (docs/theory.md §9.3).
    fn enter(&mut self, holds: &mut [Hold], q: &[f64], v: &[f64], t: f64, jump: bool) -> Result<(), EventsError> {
        holds.sort();
        let goes_on = jump && *holds == self.holds[..];
        let mut piece = std::mem::take(&mut self.piece);
        self.loads.piece_into(t, &mut piece);
        if !self.systems.contains_key(&*holds) {
            let built = self.build(holds, &piece);
            let sys = match built {
                Ok(sys) => sys,
                Err(e) => {
                    self.piece = piece;
                    return Err(e);
                }
            };
            self.systems.insert(holds.to_vec(), sys);
        } else if !self.loads.ramps.is_empty() {
            self.systems.get_mut(&*holds).expect("a cached phase").set_piece(&piece);
        }
        self.piece = piece;
        self.holds.clear();
        self.holds.extend_from_slice(holds);
        let sys = &self.systems[&self.holds];
        let nf = sys.free.len();
        if goes_on {
            let (dq, dv) = (&mut self.entering.0, &mut self.entering.1);
            dq.clear();
            dq.extend(sys.free.iter().map(|&d| q[d] - self.pre.0[d]));
            dv.clear();
            dv.extend(sys.free.iter().map(|&d| v[d] - self.pre.1[d]));
            sys.flow.add_change(dq, dv, &mut self.eta, &mut self.deta);
        } else {
            let (qf, vf) = (&mut self.entering.0, &mut self.entering.1);
            qf.clear();
            qf.extend(sys.free.iter().map(|&d| q[d]));
            vf.clear();
            vf.extend(sys.free.iter().map(|&d| v[d]));
            for x in [&mut self.eta, &mut self.deta] {
                x.clear();
                x.resize(nf, 0.0);
            }
            sys.flow.to_modal(t, qf, vf, &mut self.eta, &mut self.deta);
        }
        self.t = t;
        self.start_phase();
        let mut zero = std::mem::take(&mut self.base_zero);
        let sys = &self.systems[&self.holds];
        for (z, w) in zero.iter_mut().zip(&sys.watch) {
            if let Watch::Gap { contact, bound } = *w {
                let s = &self.sites[contact];
                // Leaving it with a speed (a rebound): a contact left at
                // rest there is decided by its derivatives' rules (§9.2),
                // which read its round-off.
                let leaving = if bound == Bound::Upper { v[s.dof] < 0.0 } else { v[s.dof] > 0.0 };
                if leaving && q[s.dof] == if bound == Bound::Upper { s.hi } else { s.lo } {
                    *z = AtBase::Leaving;
                } else if self.at_release(contact, t) {
                    *z = AtBase::Released;
                }
            }
        }
        self.base_zero = zero;
        Ok(())
    }

    /// Whether the massive contact `j`, free, is at its release at `t`:
    /// its last row within `4 δ(t)` (§9.2's resolution) is a release. It
    /// left at rest, its acceleration its force's share, 0 at the force's
    /// zero: within the resolution its speed and acceleration are the
    /// release time's round-off, not an approach (docs/theory.md §9.3,
    /// "Touches"). A massless contact's position is its force's image,
    /// not at rest.
    fn at_release(&self, j: usize, t: f64) -> bool {
        let window = 4.0 * time_resolution(t);
        !self.sites[j].massless
            && !self.holds.iter().any(|h| h.contact == j)
            && self.events.iter().rev().take_while(|r| t - r.t <= window).find(|r| r.contact == j).is_some_and(|r| r.kind == EventKind::Release)
    }

    /// The flow, events and forces of an active set (module docs).
    fn build(&self, holds: &[Hold], piece: &Piece) -> Result<System, EventsError> {
        if !self.zero.is_empty() {
            return self.build_static(holds, piece);
        }
        let n = self.n;
        let held = self.held_values(holds);
        let free: Vec<usize> = (0..n).filter(|d| !held.iter().any(|h| h.0 == *d)).collect();
        let nf = free.len();
        let sub = |a: &Mat<f64>| Mat::from_fn(nf, nf, |i, j| a[(free[i], free[j])]);
        let loads = self.loads.held(|i, j| self.k[(i, j)], &held, |x| free.iter().map(|&d| x[d]).collect());
        let basis = self.basis(holds, || Basis::new(sub(&self.m), sub(&self.k), self.c.as_ref().map(sub)))?;
        let flow = ModalFlow::with_loads(&basis, &loads);
        let (mut fns, mut quiet, mut watch) = (Vec::new(), Vec::new(), Vec::new());
        for (j, s) in self.sites.iter().enumerate() {
            if holds.iter().any(|h| h.contact == j) {
                continue;
            }
            // The contact dof's position as a functional of the modal state.
            let p = free.iter().position(|&x| x == s.dof).expect("a free dof");
            let mut unit = vec![0.0; nf];
            unit[p] = 1.0;
            self.gap_watches(j, &flow.linear(&unit, &vec![0.0; nf]), (&mut fns, &mut quiet, &mut watch));
        }
        let mut forces = Vec::new();
        for h in holds {
            let a = self.sites[h.contact].dof;
            let f = if flow.classical() { self.classical_force(&flow, &free, &held, a) } else { self.general_force(&flow, &free, &held, a) };
            self.held_force(*h, f, &mut forces, (&mut fns, &mut quiet, &mut watch));
        }
        let mut sys = System { flow, free, held, fns, quiet, watch, forces, cond: Vec::new(), g: Mat::zeros(0, 0) };
        sys.set_piece(piece);
        Ok(sys)
    }

    /// The basis of the phase of `holds` ([`FlowBases`]), built by `build`
    /// unless the shared store has it.
    fn basis(&self, holds: &[Hold], build: impl FnOnce() -> Result<Basis, EventsError>) -> Result<Arc<Basis>, EventsError> {
        let key: Vec<usize> = holds.iter().map(|h| h.contact).collect();
        basis_of(self.bases.as_deref(), &key, build)
    }

    /// Adds `Σ_d coef_d f_d(t)` (steady, waves, series) to `f`.
    fn add_loads(&self, f: &mut Functional, coef: &[f64]) {
        let loads = &self.loads;
        f.constant += coef.iter().zip(&loads.constant).map(|(c, x)| c * x).sum::<f64>();
        for (j, (g, a, w, p)) in loads.waves.iter().enumerate() {
            if f.waves.len() <= j {
                f.waves.push((0.0, *w, *p));
            }
            f.waves[j].0 += coef.iter().zip(g).map(|(c, x)| c * x).sum::<f64>() * a;
        }
        f.ramps.resize(loads.ramps.len(), 0.0);
        for (l, (h, _, _)) in loads.ramps.iter().enumerate() {
            f.ramps[l] += coef.iter().zip(h).map(|(c, x)| c * x).sum::<f64>();
        }
    }

    /// A held contact's force `r_a` (module docs) with classical damping:
    /// `β_i = K_af φ_i − k_i M_af φ_i`, `α_i = C_af φ_i − c_i M_af φ_i`, the
    /// load terms `M_af M_ff⁻¹ g_f − g_a`, plus `K_aA q_A`.
    fn classical_force(&self, flow: &ModalFlow, free: &[usize], held: &[(usize, f64)], a: usize) -> Functional {
        let nf = free.len();
        // r_a = Σ_i β_i η_i + α_i η_i' + c₀ + Σ_j c_j sin(Ω_j t + p_j).
        let mut f = Functional { beta: vec![0.0; nf], alpha: vec![0.0; nf], ramps: vec![0.0; self.loads.ramps.len()], ..Functional::default() };
        // M_af φ_i, C_af φ_i, K_af φ_i.
        for i in 0..nf {
            let (mut mp, mut cp, mut kp) = (0.0, 0.0, 0.0);
            for (r, &d) in free.iter().enumerate() {
                let ph = flow.phi[(r, i)];
                mp += self.m[(a, d)] * ph;
                kp += self.k[(a, d)] * ph;
                cp += self.c.as_ref().map_or(0.0, |c| c[(a, d)]) * ph;
            }
            f.beta[i] = kp - flow.k[i] * mp;
            f.alpha[i] = cp - flow.c[i] * mp;
            f.constant += mp * flow.g0[i];
            for (l, h) in flow.ramp_modal.iter().enumerate() {
                f.ramps[l] += mp * h[i];
            }
            for (j, hm) in flow.harmonics.iter().enumerate() {
                if f.waves.len() <= j {
                    f.waves.push((0.0, hm.omega, hm.phase));
                }
                f.waves[j].0 += mp * hm.modal[i] * hm.amplitude;
            }
        }
        for &(b, x) in held {
            f.constant += self.k[(a, b)] * x;
        }
        // − f_a(t).
        let mut coef = vec![0.0; self.n];
        coef[a] = -1.0;
        self.add_loads(&mut f, &coef);
        f
    }

    /// A free contact's gaps to its bounds, from its position: watched as
    /// its impacts (landings, for a massless one).
    fn gap_watches(&self, j: usize, position: &Functional, (fns, quiet, watch): (&mut Vec<Functional>, &mut Vec<bool>, &mut Vec<Watch>)) {
        let s = &self.sites[j];
        for (bound, f) in position.gaps(s.lo, s.hi) {
            fns.push(f);
            quiet.push(false);
            watch.push(Watch::Gap { contact: j, bound });
        }
    }

    /// A held contact's force `f` (`r`, positive at a lower bound): into
    /// `forces` (its impulses), and its zero watched as the release —
    /// unless the contact's bounds are equal (a bilateral constraint: its
    /// force takes either sign and it is never released).
    fn held_force(&self, h: Hold, f: Functional, forces: &mut Vec<(usize, Functional)>, (fns, quiet, watch): (&mut Vec<Functional>, &mut Vec<bool>, &mut Vec<Watch>)) {
        let s = &self.sites[h.contact];
        if s.lo < s.hi {
            fns.push(if h.upper { f.clone().negated() } else { f.clone() });
            quiet.push(true);
            watch.push(Watch::Release { contact: h.contact });
        }
        forces.push((h.contact, f));
    }

    /// The held contacts' `(dof, bound)`.
    fn held_values(&self, holds: &[Hold]) -> Vec<(usize, f64)> {
        holds
            .iter()
            .map(|h| {
                let s = &self.sites[h.contact];
                (s.dof, if h.upper { s.hi } else { s.lo })
            })
            .collect()
    }

    /// A held contact's force `r_a` (module docs) with a non-classical
    /// damping: `r_a = L z + M_af M_ff⁻¹ f_f(t) − f_a(t)` with the free
    /// dofs' load `f_f` (held displacements included), `L = [K_af −
    /// M_af M_ff⁻¹ K_ff, C_af − M_af M_ff⁻¹ C_ff]`, plus `K_aA q_A`.
    fn general_force(&self, flow: &ModalFlow, free: &[usize], held: &[(usize, f64)], a: usize) -> Functional {
        let nf = free.len();
        // mfinv = M_af M_ff⁻¹ (a row over the free dofs).
        let maf: Vec<f64> = free.iter().map(|&d| self.m[(a, d)]).collect();
        let mfinv = flow.minv(&maf);
        let cm = |r: usize, s: usize| self.c.as_ref().map_or(0.0, |c| c[(r, s)]);
        let row_q: Vec<f64> = (0..nf).map(|j| self.k[(a, free[j])] - (0..nf).map(|i| mfinv[i] * self.k[(free[i], free[j])]).sum::<f64>()).collect();
        let row_v: Vec<f64> = (0..nf).map(|j| cm(a, free[j]) - (0..nf).map(|i| mfinv[i] * cm(free[i], free[j])).sum::<f64>()).collect();
        let mut f = flow.linear(&row_q, &row_v);
        // The held displacements: (K_aA − M_af M_ff⁻¹ K_fA) q_A.
        for &(b, x) in held {
            f.constant += (self.k[(a, b)] - free.iter().enumerate().map(|(i, &d)| mfinv[i] * self.k[(d, b)]).sum::<f64>()) * x;
        }
        // The loads: M_af M_ff⁻¹ f_f(t) − f_a(t).
        let mut coef = vec![0.0; self.n];
        for (i, &d) in free.iter().enumerate() {
            coef[d] = mfinv[i];
        }
        coef[a] = -1.0;
        self.add_loads(&mut f, &coef);
        f
    }

    /// The time and state `(t, q, v)`.
    pub fn state(&self) -> (f64, Vec<f64>, Vec<f64>) {
        let (q, v) = self.physical();
        (self.t, q, v)
    }

    /// The time.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The events so far.
    pub fn events(&self) -> &[EventRecord] {
        &self.events
    }

    /// Which contacts are held, and at which bound (`true`: the upper).
    pub fn held(&self) -> Vec<(usize, bool)> {
        self.held_iter().collect()
    }

    /// [`held`](Self::held) without allocating.
    pub fn held_iter(&self) -> impl Iterator<Item = (usize, bool)> + '_ {
        self.holds.iter().map(|h| (h.contact, h.upper))
    }

    /// The force `r` of each contact now (0 unless held).
    pub fn forces(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.sites.len()];
        let sys = &self.systems[&self.holds];
        for (j, f) in &sys.forces {
            out[*j] = f.value(self.t, &self.eta, &self.deta);
        }
        out
    }

    /// Each contact's impulse since the last call: the impacts' impulses
    /// plus the held force's integral (exact), then reset.
    pub fn take_impulses(&mut self) -> Vec<f64> {
        let mut out = vec![0.0; self.impulses.len()];
        self.take_impulses_into(&mut out);
        out
    }

    /// [`take_impulses`](Self::take_impulses) into `out` (no allocation).
    pub fn take_impulses_into(&mut self, out: &mut [f64]) {
        out.copy_from_slice(&self.impulses);
        self.impulses.iter_mut().for_each(|x| *x = 0.0);
        // The held forces' integrals from the base to now, less what was taken.
        let sys = &self.systems[&self.holds];
        if self.t != self.base.0 {
            let base = (&self.base.1[..], &self.base.2[..]);
            for (contact, r) in &sys.forces {
                let i = r.integral(&sys.flow, self.base.0, base, (&self.eta, &self.deta), self.t - self.base.0, &mut self.tr);
                out[*contact] += i - self.taken[*contact];
                self.taken[*contact] = i;
            }
        }
    }

    /// Steps taken by the event searches so far.
    pub fn search_steps(&self) -> u64 {
        self.search.steps
    }

    /// A poll the event search calls every 256 of its steps: `true` stops
    /// the run at the time reached with [`EventsError::Interrupted`] (the
    /// state whole there; the run can go on from it). `None` removes it.
    pub fn set_interrupt(&mut self, poll: Option<crate::Interrupt>) {
        self.search.interrupt = poll;
    }

    /// Whether an event found exactly at the time a call stops at (at a
    /// search step's start there) is applied before the run stands there,
    /// as one located inside a step always is: `true` for a sampler (a
    /// row at an event's instant shows the state after it, however the
    /// search reached it: docs/theory.md §9.4); `false`, the default, for
    /// the orbits' section, which leaves an impact at the period's end to
    /// the next period (docs/orbits.md).
    pub fn take_events_at_pause(&mut self, on: bool) {
        self.search.take_at_pause = on;
    }

    /// Shares `bases` ([`FlowBases`]) for the flows of the active sets this
    /// run meets from now on (ignored unless they are of the run's
    /// structure: [`FlowBases::fits`]): the same run, bit for bit.
    pub fn share_bases(&mut self, bases: Arc<FlowBases>) {
        let contacts: Vec<(usize, bool)> = self.sites.iter().map(|s| (s.dof, s.massless)).collect();
        if bases.same(&self.m, &self.k, self.c.as_ref(), &contacts) {
            self.bases = Some(bases);
        }
    }

    /// Replaces the state (a twin run), at the current time, as [`new`](Self::new) starts.
    pub(crate) fn reset(&mut self, q: &[f64], v: &[f64]) -> Result<(), EventsError> {
        // The new state decides what is held; the old phase is kept on an error.
        let saved = std::mem::take(&mut self.holds);
        self.streak.iter_mut().for_each(Vec::clear);
        let (q, v) = self.work_state(q, v);
        let r = self.settle(self.t, q, v, None);
        if r.is_err() {
            self.holds = saved;
        }
        r
    }
}

/// A contact dof's row of `M⁻¹` and its products `(M⁻¹)_d K`, `(M⁻¹)_d C`
/// (zeros without damping), as `[m, m K, m C]`.
fn rebound_rows(full: &ModalFlow, k: &Mat<f64>, c: Option<&Mat<f64>>, dof: usize) -> [Vec<f64>; 3] {
    let m = full.minv_column(dof);
    let times = |a: &Mat<f64>| (0..m.len()).map(|s| (0..m.len()).map(|r| m[r] * a[(r, s)]).sum()).collect();
    let (km, cm) = (times(k), c.map_or_else(|| vec![0.0; m.len()], times));
    [m, km, cm]
}

/// `lo`, `hi` set to `kc` entries of `−∞`, `+∞` (no allocation once they
/// have the capacity).
fn unbounded(lo: &mut Vec<f64>, hi: &mut Vec<f64>, kc: usize) {
    lo.clear();
    lo.resize(kc, f64::NEG_INFINITY);
    hi.clear();
    hi.resize(kc, f64::INFINITY);
}

/// The accumulation time `t∞` of a run of impact times shrinking
/// geometrically (the last two ratios equal within 1 %), and `t∞ − t_k`.
fn accumulation(times: &[f64]) -> Option<(f64, f64)> {
    let k = times.len();
    if k < 4 {
        return None;
    }
    let d = |i: usize| times[k - i] - times[k - i - 1];
    let (d3, d2, d1) = (d(1), d(2), d(3));
    if !(d1 > 0.0 && d2 > 0.0 && d3 > 0.0) {
        return None;
    }
    let (r1, r2) = (d2 / d1, d3 / d2);
    if !(r2 < 1.0 && (r2 - r1).abs() <= 1e-2 * r2) {
        return None;
    }
    let rest = d3 * r2 / (1.0 - r2);
    Some((times[k - 1] + rest, rest))
}

/// What one call of [`EventDriven::next_change`] reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reached {
    /// An event, applied: the located one as logged, or `None` when it
    /// logged nothing (a contact landing at zero speed, held there from
    /// now on or flying on: no impact, docs/theory.md §9.3).
    Event(Option<EventRecord>),
    /// `t_end`, with no event before it: the run stands there.
    End,
}
