//! The grazing where the asymmetric 3-impact orbits of the oscillator
//! between symmetric stops (`x'' + 0.1 x' + x = 2 sin Ωt`, `|x| <= 1`,
//! e = 0.8; `mirror.rs`'s branch from Ω = 1.5 down) lose their slow
//! impact, located whatever the range. The transcription (`mirror.rs`, no
//! code of the crate) puts it at 1.0383070501555; the 2-impact orbits
//! beyond are asymmetric down to their branch point with the symmetric
//! ones at 1.0376426, 6.6e-4 below. The run to 0.9 listed both; the runs
//! to 1.0 and to 0.5 took their last 3-impact step farther from it (from
//! Ω = 1.0574, the slow impact at 0.041, in the run to 1.0), extrapolated
//! the slow impact's speed linearly to 0 at 1.036678 (1.037530 to 0.5),
//! jumped there onto a symmetric orbit past the branch point, listed that
//! extrapolation as the grazing and no branch point. Now the arc is
//! followed on toward the grazing until the extrapolation holds
//! (`continuation.rs`, `approach`).

use crate::mirror::GRAZING;
use signorini_orbits::front::{continue_scene, ContinueOptions};

/// From Ω = 1.5 to 1.0 and to 0.5 as `signorini continue data/scenes/
/// oscillator-two-stops.toml --param forcing.omega` runs them (its forcing
/// a cosine: the same orbits shifted in phase): `bifurcations.csv` lists
/// the 3 → 2 grazing within 1e-9 of the transcription's, then the branch
/// point (at 1.0376426, `mirror.rs`'s run to 0.9: within 1e-6, below the
/// grazing).
#[test]
fn the_grazing_is_located_on_the_branch_whatever_the_range() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator-two-stops.toml")).unwrap();
    for to in [1.0, 0.5] {
        let opts = ContinueOptions { param: "forcing.omega".into(), from: 1.5, to, period: 1, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: None };
        let done = continue_scene(text.parse().unwrap(), &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
        let csv = &done.files.iter().find(|f| f.0 == "bifurcations.csv").unwrap().1;
        let mut rows = csv.lines();
        let head: Vec<&str> = rows.next().unwrap().split(',').collect();
        let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
        let (cp, ck, cb, ca) = (col("param"), col("kind"), col("impacts_before"), col("impacts_after"));
        let listed: Vec<(String, f64, (String, String))> = rows
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                (c[ck].to_string(), c[cp].parse().unwrap(), (c[cb].to_string(), c[ca].to_string()))
            })
            .collect();
        eprintln!("to {to}: {:?}\n{listed:?}", done.lines.first());
        let graze = listed.iter().position(|(kind, w, impacts)| kind == "grazing" && impacts.0 == "3" && impacts.1 == "2" && (w - GRAZING).abs() < 1e-2);
        let Some(k) = graze else { panic!("to {to}: no 3 -> 2 grazing near {GRAZING}: {listed:?}") };
        let w = listed[k].1;
        assert!((w - GRAZING).abs() <= 1e-9, "to {to}: the grazing at {w}, {:e} from the transcription's {GRAZING}", (w - GRAZING).abs());
        let bp = listed[k + 1..].iter().find(|(kind, w, _)| kind == "branch-point" && *w < GRAZING && *w > GRAZING - 1e-3);
        assert!(bp.is_some_and(|(_, w, _)| (w - 1.0376426).abs() < 1e-6), "to {to}: no branch point at 1.0376426 after the grazing: {listed:?}");
    }
}
