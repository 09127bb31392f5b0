//! The tests of `signorini_studies::work_precision` that were unit tests in src/work_precision.rs (the
//! library is not compiled a second time as a test harness).

use signorini_studies::work_precision::*;

/// A configuration `label` at `at` with the runs `runs` and error `error`.
fn entry(label: &str, at: &str, runs: &[f64], error: f64) -> Entry {
    Entry { label: label.into(), at: at.into(), cost: Cost::of(runs).expect("finite runs"), error }
}

/// Median and range by hand: odd and even counts, unsorted input.
#[test]
fn cost_is_the_median_and_the_range_of_the_runs() {
    assert_eq!(Cost::of(&[3.0, 1.0, 2.0]), Some(Cost { median: 2.0, min: 1.0, max: 3.0, n: 3 }));
    assert_eq!(Cost::of(&[4.0, 1.0, 3.0, 2.0]), Some(Cost { median: 2.5, min: 1.0, max: 4.0, n: 4 }));
    // A slow outlier moves the range, not the median.
    assert_eq!(Cost::of(&[1.0, 1.1, 9.0, 1.2, 1.05]).map(|c| c.median), Some(1.1));
    assert_eq!(Cost::of(&[]), None);
    assert_eq!(Cost::of(&[1.0, f64::NAN]), None);
}

/// Ties are overlapping ranges, whatever the medians: [1.0, 1.2] and
/// [1.15, 1.5] tie (medians 1.1 and 1.3, 18 % apart); [1.00, 1.01] and
/// [1.02, 1.03] do not (medians 2 % apart).
#[test]
fn a_tie_is_an_overlap_of_the_ranges() {
    let a = Cost::of(&[1.0, 1.2, 1.1]).unwrap();
    let b = Cost::of(&[1.15, 1.5, 1.3]).unwrap();
    let c = Cost::of(&[2.0, 2.2, 2.1]).unwrap();
    assert!(a.ties(&b) && b.ties(&a));
    assert!(!a.ties(&c) && a.clearly_below(&c) && !c.clearly_below(&a));
    let e = Cost::of(&[1.0, 1.01, 1.005]).unwrap();
    let f = Cost::of(&[1.02, 1.03, 1.025]).unwrap();
    assert!(!e.ties(&f) && e.clearly_below(&f));
    // Touching ranges (max = min) are a tie.
    assert!(Cost::of(&[1.0, 2.0]).unwrap().ties(&Cost::of(&[2.0, 3.0]).unwrap()));
}

/// Three methods: A [1.0, 1.2] and B [1.15, 1.5] tie, C [2.0, 2.2]
/// comes next; a fourth D [1.3, 1.4] overlaps B but lies wholly above A,
/// so it leaves the first tier, and comes before C.
#[test]
fn tiers_by_hand() {
    let a = Cost::of(&[1.0, 1.2, 1.1]).unwrap();
    let b = Cost::of(&[1.15, 1.5, 1.3]).unwrap();
    let c = Cost::of(&[2.0, 2.2, 2.1]).unwrap();
    let d = Cost::of(&[1.3, 1.4, 1.35]).unwrap();
    assert_eq!(tiers(&[c, a, b]), vec![1, 0, 0]);
    assert_eq!(tiers(&[a, b, c, d]), vec![0, 0, 2, 1]);
    // Three clearly ordered costs: three tiers.
    assert_eq!(tiers(&[c, d, a]), vec![2, 1, 0]);
    assert_eq!(tiers(&[]), Vec::<usize>::new());
}

/// The ranking per target: each method at its cheapest level reaching
/// the target, ties printed as ties, the next tier as "next".
#[test]
fn ranking_and_table_by_hand() {
    let e = vec![
        entry("A lumped", "m=10", &[1.0, 1.2, 1.1], 1e-3),
        entry("A lumped", "m=20", &[5.0, 5.2, 5.1], 1e-5),
        entry("B std", "m=10", &[1.15, 1.5, 1.3], 5e-4),
        entry("C mod", "m=10", &[2.0, 2.2, 2.1], 1e-4),
    ];
    // 2e-3: A (m=10) and B tie, C next.
    assert_eq!(ranking(&e, 2e-3), vec![(0, 0), (2, 0), (3, 1)]);
    // 7e-4: A's m=10 no longer reaches it, its m=20 (5.1) does: B, then C, then A.
    assert_eq!(ranking(&e, 7e-4), vec![(2, 0), (3, 1), (1, 2)]);
    // 1e-4: C alone at tier 0, A's m=20 next.
    assert_eq!(ranking(&e, 1e-4), vec![(3, 0), (1, 1)]);
    assert_eq!(ranking(&e, 1e-6), vec![]);
    let t = cheapest_table("bar-dirichlet", &e, &[2e-3, 1e-4, 1e-6], &|l: &str| if l == "B std" { " (x)".into() } else { String::new() });
    let rows: Vec<&str> = t.lines().collect();
    assert_eq!(rows[2], "| 2e-3 | tie: A lumped m=10 / B std m=10 (x) | 1.10e0 [1.00e0, 1.20e0] / 1.30e0 [1.15e0, 1.50e0] | 1.00e-3 / 5.00e-4 | C mod m=10 | 2.10e0 [2.00e0, 2.20e0] |");
    assert_eq!(rows[3], "| 1e-4 | C mod m=10 | 2.10e0 [2.00e0, 2.20e0] | 1.00e-4 | A lumped m=20 | 5.10e0 [5.00e0, 5.20e0] |");
    assert_eq!(rows[4], "| 1e-6 | not reached at these levels | | | | |");
    // The cheapest ones (A, B, C: no exactness behind any) get one reason together.
    assert!(t.contains("Where the cheapest hold: `A lumped`, `B std`, `C mod`: a measured ranking"), "{t}");
}

/// A Courant-one winner says what it rests on and what it does not carry to.
#[test]
fn a_courant_one_winner_says_when_it_holds() {
    let e = vec![entry("cd-taylor lumped", "m=10", &[1e-6, 1.1e-6, 1.2e-6], 1e-15), entry("newmark-cn mod", "m=10", &[1e-4, 1.1e-4, 1.2e-4], 1e-2)];
    let t = cheapest_table("bar-dirichlet", &e, &[3e-2], &|_| String::new());
    assert!(t.contains("`cd-taylor lumped`: Courant number one") && t.contains("dx/dt = c on a uniform mesh") && t.contains("does not carry to other meshes, loads or obstacles"), "{t}");
    assert!(!t.contains("`newmark-cn mod`:"), "only the cheapest are explained: {t}");
    assert!(condition("bar-dirichlet", "newmark-cn mod r=4").contains("truncation error"));
    assert!(condition("bar-neumann-gravity", "newmark-ii std P3").starts_with("P3 elements"));
    assert!(condition("beam-fig2", "beta-scheme(0.5) massless-tip r=8").contains("massless-tip"));
}

/// Five tied: four are named, "… (+1 tied)", and only the named ones
/// are explained (the fifth, by median, is the Courant-one scheme).
#[test]
fn only_the_named_cheapest_are_explained() {
    let mut e: Vec<Entry> = (0..4).map(|k| entry(&format!("s{k} std"), "m=10", &[1.0 + 0.01 * k as f64, 2.0], 1e-2)).collect();
    e.push(entry("cd-taylor lumped", "m=10", &[1.5, 1.9], 1e-2));
    let t = cheapest_table("bar-dirichlet", &e, &[3e-2], &|_| String::new());
    assert!(t.contains("| tie: s0 std m=10 / s1 std m=10 / s2 std m=10 / s3 std m=10 / … (+1 tied) |"), "{t}");
    assert!(t.contains("`s0 std`, `s1 std`, `s2 std`, `s3 std`: a measured ranking") && !t.contains("Courant"), "{t}");
}

/// The frontier by hand: P2 and P3 are dominated by P1 (P3 at the same
/// cost, worse), P4 by P7 (cheaper, same error), P6 has no cost.
#[test]
fn frontier_by_hand() {
    let p = [(1.0, 1e-1), (2.0, 1e-2), (3.0, 5e-2), (2.0, 2e-2), (5.0, 1e-3), (0.5, 0.5), (f64::NAN, 1e-6), (4.0, 1e-3)];
    assert_eq!(frontier(&p), vec![5, 0, 1, 7]);
    // An exact (zero-error) cheapest point is the whole frontier.
    assert_eq!(frontier(&[(2.0, 1e-3), (1.0, 0.0), (3.0, 1e-9)]), vec![1]);
    assert_eq!(frontier(&[]), Vec::<usize>::new());
}

/// The chart: the frontier as a staircase to the largest cost drawn,
/// then the named configurations only (ten configurations in, the
/// winner, the frontier's owners and the next, at most six, out).
#[test]
fn the_chart_draws_the_frontier_and_a_few_curves() {
    let mut e = vec![entry("fast coarse", "m=10", &[1.0, 1.0, 1.0], 1e-1), entry("fast coarse", "m=20", &[2.0, 2.0, 2.0], 5e-2), entry("accurate", "m=10", &[3.0, 3.0, 3.0], 1e-3)];
    for k in 0..8 {
        e.push(entry(&format!("slow {k}"), "m=10", &[10.0 + k as f64, 10.0 + k as f64, 10.0 + k as f64], 1e-2));
    }
    let (s, drawn) = wp_series(&e, &[3e-1, 1e-2]);
    assert_eq!(s[0].points, vec![(1.0, 1e-1), (2.0, 1e-1), (2.0, 5e-2), (3.0, 5e-2), (3.0, 1e-3), (10.0, 1e-3)]);
    let labels: Vec<&str> = s[1..].iter().map(|x| x.label.as_str()).collect();
    // 3e-1: fast coarse; 1e-2: accurate; next at 3e-1: accurate, at 1e-2: slow 0.
    assert_eq!(labels, vec!["fast coarse", "accurate", "slow 0"]);
    assert_eq!(drawn, 3);
    // Many winners: at most six curves.
    let many: Vec<Entry> = (0..10).map(|k| entry(&format!("c{k}"), "m=10", &[1.0, 1.0 + 1e-3 * k as f64], 1e-3 * (1.0 + k as f64))).collect();
    let (s, drawn) = wp_series(&many, &[1e-1]);
    assert_eq!((s.len(), drawn), (1 + MAX_CURVES, MAX_CURVES));
    // Ten tied at a coarse target do not crowd out the one reaching a fine one.
    let mut more = many.clone();
    more.push(entry("fine", "m=640", &[100.0, 101.0], 1e-6));
    let (s, _) = wp_series(&more, &[1e-1, 1e-5]);
    let labels: Vec<&str> = s[1..].iter().map(|x| x.label.as_str()).collect();
    assert_eq!(labels, vec!["c0", "fine", "c1", "c2", "c3", "c4"]);
}
