//! A scheme's fused kernel — a step whose right-hand side is made inside
//! the solve's sweeps, where the matrices allow it (`Nsga`'s and
//! `ContactStabilized`'s `Tridiagonal`, the P1 bar) — with the switches
//! its tests and benchmarks use: off and back on, and the baseline x86-64
//! build of its kernel instead of the AVX2 one. None changes a result.

/// The kernel, if it applies, and whether it is switched on (by default
/// where it applies).
pub(crate) struct FusedSwitch<T> {
    kernel: Option<T>,
    on: bool,
}

impl<T> FusedSwitch<T> {
    /// `kernel` (`None` where it does not apply), switched on.
    pub(crate) fn new(kernel: Option<T>) -> Self {
        Self { on: kernel.is_some(), kernel }
    }

    /// The kernel, where it applies and is switched on.
    #[inline]
    pub(crate) fn active(&self) -> Option<&T> {
        self.kernel.as_ref().filter(|_| self.on)
    }

    /// Switches the kernel on (where it applies) or off.
    pub(crate) fn set(&mut self, on: bool) {
        self.on = on && self.kernel.is_some();
    }

    /// Whether the kernel is in use.
    pub(crate) fn is_on(&self) -> bool {
        self.on
    }

    /// The kernel, where it applies (on or off).
    pub(crate) fn kernel_mut(&mut self) -> Option<&mut T> {
        self.kernel.as_mut()
    }
}

/// The public face of a scheme's [`FusedSwitch`] field `$field` (whose
/// kernel has an `avx2: bool`): `set_fused`, `fused` and `portable`, hidden
/// from the docs (for tests and benchmarks). Inside the scheme's `impl`.
macro_rules! fused_switches {
    ($field:ident) => {
        /// Switches the fused step off or back on (where it applies; on by
        /// default): for tests comparing it with the plain step, and
        /// benchmarks. Changes no result.
        #[doc(hidden)]
        pub fn set_fused(&mut self, on: bool) {
            self.$field.set(on);
        }

        /// Whether the fused step is in use.
        #[doc(hidden)]
        pub fn fused(&self) -> bool {
            self.$field.is_on()
        }

        /// The fused step's kernel in its baseline x86-64 build, AVX2 or
        /// not: for tests. Changes no result.
        #[doc(hidden)]
        pub fn portable(mut self) -> Self {
            if let Some(t) = self.$field.kernel_mut() {
                t.avx2 = false;
            }
            self
        }
    };
}
pub(crate) use fused_switches;
