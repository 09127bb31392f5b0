//! One entry for every lockstep engine and lane count, compiled once here
//! ([`LockstepBatch`]): the scheme ([`LockstepScheme`], the registry's
//! value) and the width (2, 4, 8 or 16 lanes) are chosen at run time, at
//! construction; every later call reaches the engine through one pointer.
//! The sweep and the tests take it, so no other crate instantiates an
//! engine's generic code again (each engine × width costs seconds of
//! compile time: the step is built three times, for the baseline x86-64
//! target, AVX2 and AVX-512F).
//!
//! The time loop reads every lane's results of a step at once
//! ([`Lockstep::results`]), so the dispatch stays outside its per-lane work.

use crate::lanes::{Lockstep, LockstepLane};
use crate::{
    Active, CdLagrangeLockstep, ContactStabilizedLockstep, D1Level, D1MinusLinearLockstep, LaneResults, LockstepScheme, MoreauJeanCombinedLockstep, MoreauJeanLockstep, NsgaLockstep,
    PaoliSchatzmanLockstep, SchemeError,
};

/// The lane counts a [`LockstepBatch`] is built for (its width): a batch
/// of fewer lanes pads the rest with copies of its lane 0.
pub const LOCKSTEP_WIDTHS: [usize; 4] = [2, 4, 8, 16];

/// A vector an engine keeps per lane besides `U^n`
/// ([`LockstepBatch::vector_into`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LaneVector {
    /// `U^{n-1}` (Paoli–Schatzman).
    PreviousDisplacement,
    /// `V^n` (Moreau–Jean, also projected and combined; NSGA;
    /// contact-stabilized; Schindler and Acary's).
    Velocity,
    /// `V^{n-1/2}` (CD-Lagrange).
    HalfStepVelocity,
    /// NSGA's acceleration-like variable `a^n`.
    AccelerationLike,
    /// The contact-stabilized scheme's stabilised predictor.
    Predictor,
}

/// The parts of a lane's contact force in Schindler and Acary's engine
/// ([`LockstepBatch::impact_parts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactParts {
    /// The impulse `Λ`.
    pub impulse: f64,
    /// The forces `(λ⁺, λ⁻)`.
    pub forces: (f64, f64),
    /// Whether the step had an impact.
    pub impact: bool,
}

/// What the batch needs of an engine besides [`Lockstep`] (implemented
/// for every engine and width below).
trait Engine: Lockstep + Send {
    /// Restricts the builds of the step (`avx2`, `avx512` false: not that one).
    fn restrict(&mut self, avx2: bool, avx512: bool);
    /// The builds the step runs: (AVX2, AVX-512).
    fn builds(&self) -> (bool, bool);
    /// Lane `k`'s `v` into `out`; false if the engine keeps no such vector.
    fn vector_into(&self, _v: LaneVector, _k: usize, _out: &mut [f64]) -> bool {
        false
    }
    fn impact_parts(&self, _k: usize) -> Option<ImpactParts> {
        None
    }
    fn contact_level(&self) -> Option<D1Level> {
        None
    }
    fn passes(&self) -> Option<u64> {
        None
    }
}

/// [`Engine`] for an engine with the builds of `lockstep_builds!`; the
/// vectors it keeps (`LaneVector` => its method), then its own items.
macro_rules! engine {
    ($engine:ident { $($v:ident => $m:ident),* } $($own:item)*) => {
        impl<const L: usize> Engine for $engine<L> {
            fn restrict(&mut self, avx2: bool, avx512: bool) {
                $engine::restrict_builds(self, avx2, avx512)
            }
            fn builds(&self) -> (bool, bool) {
                (self.uses_avx2(), self.uses_avx512())
            }
            fn vector_into(&self, v: LaneVector, k: usize, out: &mut [f64]) -> bool {
                match v {
                    $(LaneVector::$v => self.$m(k, out),)*
                    #[allow(unreachable_patterns)]
                    _ => return false,
                }
                true
            }
            $($own)*
        }
    };
}

engine!(PaoliSchatzmanLockstep { PreviousDisplacement => previous_displacement_into });
engine!(MoreauJeanLockstep { Velocity => velocity_into });
engine!(NsgaLockstep { Velocity => velocity_into, AccelerationLike => acceleration_like_into });
engine!(ContactStabilizedLockstep { Velocity => velocity_into, Predictor => predictor_into });
engine!(CdLagrangeLockstep { HalfStepVelocity => half_step_velocity_into });
engine!(D1MinusLinearLockstep { Velocity => velocity_into }
    fn impact_parts(&self, k: usize) -> Option<ImpactParts> {
        Some(ImpactParts { impulse: self.impulse(k), forces: self.forces(k), impact: self.impact(k) })
    }
    fn contact_level(&self) -> Option<D1Level> {
        Some(D1MinusLinearLockstep::contact_level(self))
    }
);
engine!(MoreauJeanCombinedLockstep { Velocity => velocity_into }
    fn passes(&self) -> Option<u64> {
        Some(MoreauJeanCombinedLockstep::passes(self))
    }
);

/// The engine of `scheme` with `L` lanes.
fn engine<const L: usize>(scheme: LockstepScheme, dt: f64, lanes: Vec<LockstepLane>) -> Result<Box<dyn Engine>, SchemeError> {
    Ok(match scheme {
        LockstepScheme::PaoliSchatzman { beta, .. } => Box::new(PaoliSchatzmanLockstep::<L>::new(beta, dt, lanes)?),
        LockstepScheme::MoreauJean { theta, gamma, .. } => Box::new(MoreauJeanLockstep::<L>::new(theta, gamma, dt, lanes)?),
        LockstepScheme::MoreauJeanProjected { theta, gamma, .. } => Box::new(MoreauJeanLockstep::<L>::projected(theta, gamma, dt, lanes)?),
        LockstepScheme::Nsga { rho_inf, .. } => Box::new(NsgaLockstep::<L>::new(rho_inf, dt, lanes)?),
        LockstepScheme::ContactStabilized => Box::new(ContactStabilizedLockstep::<L>::new(dt, lanes)?),
        LockstepScheme::CdLagrange { .. } => Box::new(CdLagrangeLockstep::<L>::new(dt, lanes)?),
        LockstepScheme::D1MinusLinear { level, .. } => Box::new(D1MinusLinearLockstep::<L>::new(level, dt, lanes)?),
        LockstepScheme::MoreauJeanCombined { theta, .. } => Box::new(MoreauJeanCombinedLockstep::<L>::new(theta, dt, lanes)?),
    })
}

/// Runs of one lockstep-capable scheme that share a step matrix, stepped
/// together by its engine ([`PaoliSchatzmanLockstep`],
/// [`MoreauJeanLockstep`] (also [`projected`](MoreauJeanLockstep::projected)),
/// [`NsgaLockstep`], [`ContactStabilizedLockstep`], [`CdLagrangeLockstep`],
/// [`D1MinusLinearLockstep`], [`MoreauJeanCombinedLockstep`]) of 2, 4, 8 or
/// 16 lanes, chosen at construction: each lane bit for bit its single run
/// (the engines' docs). Non-generic: every engine and width is compiled
/// once, in this crate.
pub struct LockstepBatch {
    engine: Box<dyn Engine>,
    scheme: LockstepScheme,
    width: usize,
}

impl std::fmt::Debug for LockstepBatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LockstepBatch").field("scheme", &self.scheme).field("width", &self.width).field("lanes", &self.engine.lanes()).finish()
    }
}

impl LockstepBatch {
    /// The engine of `scheme` (its parameters; each lane brings its own
    /// restitution, [`LockstepLane::restitution`], and the scheme's is
    /// not read) with step `dt` on `lanes`, of the narrowest width in
    /// [`LOCKSTEP_WIDTHS`] that holds them.
    ///
    /// Errors: what the engine refuses ([`SchemeError`]: its parameters,
    /// the lanes' problems, and [`SchemeError::Size`] for no lane or more
    /// than 16).
    pub fn new(scheme: LockstepScheme, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        let width = LOCKSTEP_WIDTHS.iter().copied().find(|&w| w >= lanes.len()).unwrap_or(LOCKSTEP_WIDTHS[LOCKSTEP_WIDTHS.len() - 1]);
        Self::with_width(scheme, width, dt, lanes)
    }

    /// [`new`](Self::new) on an engine of `width` lanes (one of
    /// [`LOCKSTEP_WIDTHS`]; [`SchemeError::Invalid`] for another), which
    /// refuses more lanes than that ([`SchemeError::Size`]).
    pub fn with_width(scheme: LockstepScheme, width: usize, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        let engine = match width {
            2 => engine::<2>(scheme, dt, lanes),
            4 => engine::<4>(scheme, dt, lanes),
            8 => engine::<8>(scheme, dt, lanes),
            16 => engine::<16>(scheme, dt, lanes),
            _ => Err(SchemeError::Invalid { field: "width", value: width as f64, allowed: "2, 4, 8 or 16 lanes" }),
        }?;
        Ok(Self { engine, scheme, width })
    }

    /// The scheme and its parameters, as given.
    pub fn scheme(&self) -> LockstepScheme {
        self.scheme
    }

    /// The engine's lane count (at least [`lanes`](Lockstep::lanes)).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Uses the baseline x86-64 (SSE2) build of the step even where the CPU
    /// has AVX2 (the same bits; for tests and measurements).
    pub fn portable(mut self) -> Self {
        self.engine.restrict(false, false);
        self
    }

    /// Uses at most the AVX2 build, even where the CPU has AVX-512 (the
    /// same bits; for tests and measurements).
    pub fn without_avx512(mut self) -> Self {
        self.engine.restrict(true, false);
        self
    }

    /// Whether the step runs the AVX2 build.
    pub fn uses_avx2(&self) -> bool {
        self.engine.builds().0
    }

    /// Whether the step runs the AVX-512 build.
    pub fn uses_avx512(&self) -> bool {
        self.engine.builds().1
    }

    /// Lane `k`'s vector `v` into `out` (length [`dofs`](Lockstep::dofs));
    /// false (and `out` untouched) if the engine keeps no such vector.
    #[track_caller]
    pub fn vector_into(&self, v: LaneVector, k: usize, out: &mut [f64]) -> bool {
        self.engine.vector_into(v, k, out)
    }

    /// The parts of lane `k`'s contact force in the last step (Schindler and
    /// Acary's engine, `d1-minus-linear`; `None` for the others).
    #[track_caller]
    pub fn impact_parts(&self, k: usize) -> Option<ImpactParts> {
        self.engine.impact_parts(k)
    }

    /// The level of the contact forces (`d1-minus-linear`; `None` for the
    /// other engines).
    pub fn contact_level(&self) -> Option<D1Level> {
        self.engine.contact_level()
    }

    /// The passes the batch has taken, a step redone counting again
    /// (`moreau-jean-combined`; `None` for the other engines).
    pub fn passes(&self) -> Option<u64> {
        self.engine.passes()
    }
}

impl Lockstep for LockstepBatch {
    fn lanes(&self) -> usize {
        self.engine.lanes()
    }
    fn dofs(&self) -> usize {
        self.engine.dofs()
    }
    fn contact_dof(&self) -> usize {
        self.engine.contact_dof()
    }
    fn dt(&self) -> f64 {
        self.engine.dt()
    }
    fn level(&self) -> usize {
        self.engine.level()
    }
    fn time(&self) -> f64 {
        self.engine.time()
    }
    fn lambda_time(&self) -> f64 {
        self.engine.lambda_time()
    }
    fn step(&mut self) -> usize {
        self.engine.step()
    }
    fn displacement_into(&self, k: usize, out: &mut [f64]) {
        self.engine.displacement_into(k, out)
    }
    fn value(&self, k: usize, i: usize) -> f64 {
        self.engine.value(k, i)
    }
    fn contact_force(&self, k: usize) -> f64 {
        self.engine.contact_force(k)
    }
    fn contact_status(&self, k: usize) -> Active {
        self.engine.contact_status(k)
    }
    fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        self.engine.lane_failure(k)
    }
    fn results(&self) -> LaneResults<'_> {
        self.engine.results()
    }
}
