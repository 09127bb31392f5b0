//! # signorini
//!
//! Facade of the signorini workspace: re-exports the crates so a user can
//! depend on one name. Each crate is also usable alone:
//!
//! * [`fem`]: P1–P3 bar and Hermite beam matrices with every mass treatment, banded LDLᵀ;
//! * [`contact`]: the closed-form contact projection;
//! * [`exact`]: exact benchmark solutions;
//! * [`norms`]: exact error norms accumulated while stepping;
//! * [`reduce`]: reduced models with a massless contact boundary;
//! * [`schemes`]: the time integrators;
//! * [`run`]: problems, the time loop, observers and convergence studies.

pub use signorini_contact as contact;
pub use signorini_exact as exact;
pub use signorini_fem as fem;
pub use signorini_norms as norms;
pub use signorini_reduce as reduce;
pub use signorini_run as run;
pub use signorini_schemes as schemes;
