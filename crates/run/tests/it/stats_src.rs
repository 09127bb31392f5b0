//! The tests of `signorini_run::stats` that were unit tests in src/stats.rs (the
//! library is not compiled a second time as a test harness).

use signorini_run::stats::*;

#[test]
fn t_quantiles_match_the_tables() {
    // Two-sided 95 %: t_{0.975, df}.
    for (df, q) in [(1, 12.706_204_736), (2, 4.302_652_730), (5, 2.570_581_836), (9, 2.262_157_163), (19, 2.093_024_054), (29, 2.045_229_642), (1000, 1.962_339_081)] {
        let got = t_quantile(0.975, df);
        assert!((got - q).abs() < 1e-8 * q, "df {df}: {got} against {q}");
        assert!((t_cdf(got, df) - 0.975).abs() < 1e-13);
    }
    assert!((t_quantile(0.025, 9) + 2.262_157_163).abs() < 1e-8);
}

#[test]
fn batch_means_of_a_constant_and_refusals() {
    let i = batch_means(&[2.0; 100], 10, 0.95).unwrap();
    assert_eq!((i.mean, i.low, i.high), (2.0, 2.0, 2.0));
    assert!(batch_means(&[1.0; 5], 10, 0.95).is_none());
    assert!(batch_means(&[1.0; 50], 1, 0.95).is_none());
}
