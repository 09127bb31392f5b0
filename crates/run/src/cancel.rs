//! A cancel token: how a caller stops a run or a sweep cleanly from another
//! thread or a signal handler.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A cheap, cloneable cancel token (an `Arc<AtomicBool>`): every clone
/// shares one flag. A run ([`RunConfig::interrupt`](crate::RunConfig::interrupt))
/// checks it before each step, and a step of unbounded work (the
/// event-driven scheme's, inside its event search: every 256 search steps)
/// during it, and stops with
/// [`RunError::Interrupted`](crate::RunError::Interrupted) at the last
/// whole level; a sweep checks it
/// between runs and before each lockstep step.
///
/// ```
/// use signorini_run::Cancel;
///
/// let token = Cancel::new();
/// let seen_by_the_run = token.clone();
/// assert!(!seen_by_the_run.is_cancelled());
/// token.cancel();
/// assert!(seen_by_the_run.is_cancelled());
/// ```
///
/// A signal handler sets the shared flag itself: hand it
/// [`flag`](Self::flag) (e.g. `signal_hook::flag::register(SIGINT, token.flag())`).
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not cancelled yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Cancels: every clone sees it from now on.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the token was cancelled.
    #[inline]
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The shared flag, for code that sets an `Arc<AtomicBool>` itself (a
    /// signal handler registered with `signal_hook::flag::register`):
    /// setting it to `true` cancels this token.
    pub fn flag(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.0)
    }
}
