//! A sweep of the paper's beam (J = 19, β = 1/2, e = 0, dt = 5e-6): the
//! single `PaoliSchatzman` step against `PaoliSchatzmanLockstep` with
//! `L = 1, 2, 4, 8, 16` runs sharing the step matrix, in ns per run-step
//! (the sweeps use up to 16).
//!
//! `cargo bench -p signorini-run --bench lockstep`; divan's throughput is in
//! run-steps/s (one item = one step of one run). `frequency_*`: every lane
//! its own ω (one `mean` per lane and step); `amplitude_*`: one ω, the
//! amplitudes differ (the profile's mean is computed once per step);
//! `two_threads_*`: two batches of `L` on two rayon threads;
//! `frequency_avx2_*`: the AVX2 build where the CPU also has AVX-512;
//! `frequency_baseline_*`: the baseline x86-64 (SSE2) build where the CPU has AVX2.
//! `moreau_jean_single` and `moreau_jean_frequency_*`: the same for
//! `moreau-jean` (θ = 1/2, e = 0, γ = 1/2): the single `MoreauJean` step
//! against `MoreauJeanLockstep`; `nsga_single` and `nsga_frequency_*`:
//! the same for `nsga(0.5)` (ρ∞ = 1/2, e = 0): the single `Nsga` step
//! against `NsgaLockstep`; `stabilized_single` and
//! `stabilized_frequency_*`: the same for `contact-stabilized`: the single
//! `ContactStabilized` step against `ContactStabilizedLockstep`;
//! `d1_single`, `d1_frequency_*`, `d1_velocity_single` and
//! `d1_velocity_frequency_*`: the same for `d1-minus-linear(0)` on the
//! acceleration and the velocity level (explicit: dt = 5e-6 is below its
//! limit 1.2395e-5 on J = 19): the single `D1MinusLinear` step against
//! `D1MinusLinearLockstep`; `combined_single` and `combined_frequency_*`:
//! the same for `moreau-jean-combined(1,0)` (θ = 1, the sweeps' setting:
//! with θ = 1/2 the paper's beam blows up): the single `MoreauJeanCombined`
//! step against `MoreauJeanCombinedLockstep`.

use divan::counter::ItemsCount;
use divan::Bencher;
use signorini_run::beam::Pipe;
use signorini_schemes::{
    ContactStabilized, ContactStabilizedLockstep, D1Level, D1MinusLinear, D1MinusLinearLockstep, Lockstep, LockstepLane, MoreauJean, MoreauJeanCombined, MoreauJeanCombinedLockstep,
    MoreauJeanLockstep, Nsga, NsgaLockstep, PaoliSchatzman, PaoliSchatzmanLockstep, Stepper,
};

fn main() {
    divan::main();
}

const DT: f64 = 5e-6;
const STEPS: usize = 10_000;

/// Lane `k` of a sweep: ω = 10 + k (frequency) or A = 0.2 + 0.01 k (amplitude).
fn lane(k: usize, frequency: bool) -> LockstepLane {
    let p = Pipe::paper();
    let (a, w) = p.support;
    let support = if frequency { (a, w + k as f64) } else { (a + 0.01 * k as f64, w) };
    let (_, dynamics, initial) = Pipe { support, ..p }.dynamics(19).unwrap();
    LockstepLane { dynamics, initial, restitution: 0.0 }
}

fn batch<const L: usize>(frequency: bool) -> PaoliSchatzmanLockstep<L> {
    PaoliSchatzmanLockstep::<L>::new(0.5, DT, (0..L).map(|k| lane(k, frequency)).collect()).unwrap()
}

/// One run, `PaoliSchatzman::step`: ns per step.
#[divan::bench]
fn single(bencher: Bencher) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            PaoliSchatzman::new("single".into(), l.dynamics, 0.5, 0.0, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep in lockstep: ns per run-step.
#[divan::bench(consts = [1, 2, 4, 8, 16])]
fn frequency<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| batch::<L>(true)).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// `L` runs of an amplitude sweep in lockstep: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn amplitude<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| batch::<L>(false)).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// Two frequency batches of `L` on two rayon threads: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn two_threads<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(2 * STEPS * L)).with_inputs(|| (batch::<L>(true), batch::<L>(true))).bench_local_values(|(mut a, mut b)| {
        let go = |s: &mut PaoliSchatzmanLockstep<L>| {
            for _ in 0..STEPS {
                divan::black_box(s.step());
            }
        };
        rayon::join(|| go(&mut a), || go(&mut b));
        (a, b)
    });
}

/// The AVX2 build of the step where the CPU also has AVX-512 (`without_avx512()`), frequency sweep: ns per run-step.
#[divan::bench(consts = [8, 16])]
fn frequency_avx2<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| batch::<L>(true).without_avx512()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// The baseline x86-64 build of the step (SSE2, `portable()`), frequency sweep: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn frequency_baseline<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| batch::<L>(true).portable()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// One run, `MoreauJean::step` (θ = 1/2, e = 0, γ = 1/2): ns per step.
#[divan::bench]
fn moreau_jean_single(bencher: Bencher) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            MoreauJean::new("single".into(), l.dynamics, 0.5, 0.0, 0.5, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep with `MoreauJeanLockstep`: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn moreau_jean_frequency<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| MoreauJeanLockstep::<L>::new(0.5, 0.5, DT, (0..L).map(|k| lane(k, true)).collect()).unwrap()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// One run, `Nsga::step` (ρ∞ = 1/2, e = 0): ns per step.
#[divan::bench]
fn nsga_single(bencher: Bencher) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            Nsga::new("single".into(), l.dynamics, 0.5, 0.0, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep with `NsgaLockstep`: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn nsga_frequency<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| NsgaLockstep::<L>::new(0.5, DT, (0..L).map(|k| lane(k, true)).collect()).unwrap()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// One run, `ContactStabilized::step`: ns per step.
#[divan::bench]
fn stabilized_single(bencher: Bencher) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            ContactStabilized::new("single".into(), l.dynamics, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep with `ContactStabilizedLockstep`: ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn stabilized_frequency<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| ContactStabilizedLockstep::<L>::new(DT, (0..L).map(|k| lane(k, true)).collect()).unwrap()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// One run, `D1MinusLinear::step` on `level` (e = 0): ns per step.
fn d1_single_on(bencher: Bencher, level: D1Level) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            D1MinusLinear::at_level(level, "single".into(), l.dynamics, 0.0, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep with `D1MinusLinearLockstep` on `level`: ns per run-step.
fn d1_frequency_on<const L: usize>(bencher: Bencher, level: D1Level) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| D1MinusLinearLockstep::<L>::new(level, DT, (0..L).map(|k| lane(k, true)).collect()).unwrap()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}

/// One run, `D1MinusLinear::step` (acceleration level, e = 0): ns per step.
#[divan::bench]
fn d1_single(bencher: Bencher) {
    d1_single_on(bencher, D1Level::Acceleration);
}

/// `L` runs of a frequency sweep with `D1MinusLinearLockstep` (acceleration level): ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn d1_frequency<const L: usize>(bencher: Bencher) {
    d1_frequency_on::<L>(bencher, D1Level::Acceleration);
}

/// One run, `D1MinusLinear::step` (velocity level, e = 0): ns per step.
#[divan::bench]
fn d1_velocity_single(bencher: Bencher) {
    d1_single_on(bencher, D1Level::Velocity);
}

/// `L` runs of a frequency sweep with `D1MinusLinearLockstep` (velocity level): ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn d1_velocity_frequency<const L: usize>(bencher: Bencher) {
    d1_frequency_on::<L>(bencher, D1Level::Velocity);
}

/// One run, `MoreauJeanCombined::step` (θ = 1, e = 0): ns per step.
#[divan::bench]
fn combined_single(bencher: Bencher) {
    bencher
        .counter(ItemsCount::new(STEPS))
        .with_inputs(|| {
            let l = lane(0, true);
            MoreauJeanCombined::new("single".into(), l.dynamics, 1.0, 0.0, DT, &l.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..STEPS {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// `L` runs of a frequency sweep with `MoreauJeanCombinedLockstep` (θ = 1): ns per run-step.
#[divan::bench(consts = [4, 8, 16])]
fn combined_frequency<const L: usize>(bencher: Bencher) {
    bencher.counter(ItemsCount::new(STEPS * L)).with_inputs(|| MoreauJeanCombinedLockstep::<L>::new(1.0, DT, (0..L).map(|k| lane(k, true)).collect()).unwrap()).bench_local_values(|mut b| {
        for _ in 0..STEPS {
            divan::black_box(b.step());
        }
        b
    });
}
