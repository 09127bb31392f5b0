//! The seeded proptest runner over both generators ([`fuzz`]).

use crate::check::{check_doc, check_text};
use crate::config::Config;
use crate::documents::documents;
use crate::mutations::mutations;
use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};

// ----------------------------------------------------------------- driver --

/// Counts of a fuzz run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Generated documents checked.
    pub documents: u32,
    /// Mutated shipped scenes checked.
    pub mutations: u32,
}

/// A failing input, shrunk by proptest.
#[derive(Clone, Debug)]
pub struct Failure {
    /// Which generator.
    pub generator: &'static str,
    /// What is wrong.
    pub reason: String,
    /// The input text.
    pub input: String,
}

/// Runs `cases` generated documents and `cases` mutations of `scenes` from
/// `seed` (same seed, same inputs); `trace` sees every input before it is
/// read (for a long run: to find an input that aborts the process).
pub fn fuzz(cfg: Config, cases: u32, seed: u64, scenes: Vec<String>, trace: &dyn Fn(&str)) -> Result<Stats, Failure> {
    let runner = |salt: u64| {
        let mut bytes = [0u8; 32];
        bytes[..8].copy_from_slice(&seed.to_le_bytes());
        bytes[8..16].copy_from_slice(&salt.to_le_bytes());
        let config = RunnerConfig { cases, failure_persistence: None, max_shrink_iters: 2048, ..RunnerConfig::default() };
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
    };
    let fail = |generator: &'static str, e: TestError<String>| match e {
        TestError::Fail(reason, input) => Failure { generator, reason: reason.to_string(), input },
        TestError::Abort(reason) => Failure { generator, reason: reason.to_string(), input: String::new() },
    };
    let mut stats = Stats::default();
    let docs = documents(cfg).prop_map(|d| (d.render(), d));
    runner(1)
        .run(&docs, |(text, doc)| {
            trace(&text);
            check_doc(&doc, cfg).map_err(TestCaseError::fail)
        })
        .map_err(|e| {
            fail(
                "documents",
                match e {
                    TestError::Fail(r, (text, _)) => TestError::Fail(r, text),
                    TestError::Abort(r) => TestError::Abort(r),
                },
            )
        })?;
    stats.documents = cases;
    if !scenes.is_empty() {
        runner(2)
            .run(&mutations(scenes), |text| {
                trace(&text);
                check_text(&text, cfg).map(|_| ()).map_err(TestCaseError::fail)
            })
            .map_err(|e| fail("mutations", e))?;
        stats.mutations = cases;
    }
    Ok(stats)
}
