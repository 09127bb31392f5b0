//! The unit tests of `crates/sweep/src/setup.rs` (its `Manifest`,
//! `#[doc(hidden)] pub` for them), moved unchanged: the sweep library is not
//! compiled a second time as a test harness (about 30 s of processor time),
//! and this binary, which links it already, holds them (the sweep crate has
//! no test binary of its own).
use signorini_sweep::Manifest;
use std::fmt::Write as _;

/// The manifest as it was written by hand before the toml crate wrote
/// it (`writeln!` with `{:?}` for strings and floats).
fn by_hand(m: &Manifest) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# signorini sweep manifest: merge checks that shards share the id");
    let _ = writeln!(s, "id = \"{}\"", m.id);
    let _ = writeln!(s, "scene = {:?}", m.scene);
    let _ = writeln!(s, "param = {:?}", m.param);
    let _ = writeln!(s, "from = {:?}\nto = {:?}\ncount = {}\nlog = {}", m.from, m.to, m.count, m.log);
    if let Some(p) = &m.param2 {
        let _ = writeln!(s, "param2 = {:?}\nfrom2 = {:?}\nto2 = {:?}\ncount2 = {}\nlog2 = {}", p, m.from2.unwrap(), m.to2.unwrap(), m.count2.unwrap(), m.log2.unwrap());
    }
    let _ = writeln!(s, "transient = {:?}\nrecord = {:?}\nphase = {:?}\nperiod_tol = {:?}\nfollow = {}", m.transient, m.record, m.phase, m.period_tol, m.follow);
    if m.impacts == Some(false) {
        let _ = writeln!(s, "impacts = false");
    }
    if let (Some([i, n]), Some([a, b])) = (m.shard, m.runs) {
        let _ = writeln!(s, "shard = [{i}, {n}]\nruns = [{a}, {b}]");
    }
    s
}

fn manifest(from: f64, to: f64, scene: &str, map: bool, shard: bool) -> Manifest {
    Manifest {
        id: "a60189f356524119".into(),
        scene: scene.into(),
        param: "support.omega".into(),
        from,
        to,
        count: 1000,
        log: false,
        param2: map.then(|| "stop.0.hi".into()),
        from2: map.then_some(to),
        to2: map.then_some(from),
        count2: map.then_some(7),
        log2: map.then_some(true),
        transient: 20.0,
        record: 2.5,
        phase: from.abs().min(6.0),
        period_tol: 0.001,
        follow: !map,
        impacts: map.then_some(false),
        shard: shard.then_some([1, 4]),
        runs: shard.then_some([250, 500]),
    }
}

/// The toml crate writes what the hand-written manifest was, byte for
/// byte, for numbers in `[1e-4, 1e16)` in magnitude (or 0) and names
/// without `"` or `\` (the reference sweep's among them), and reads it
/// back to the same values.
#[test]
fn the_toml_manifest_is_the_hand_written_one() {
    let floats = [4.0, 16.0, 0.0, 0.001, 0.1, 1e-4, 123456789.125, 1e15, 9.999e15, -3.5, 1.0 / 3.0, 9.5, 2.0 * std::f64::consts::PI];
    for (k, &from) in floats.iter().enumerate() {
        let to = floats[(k + 3) % floats.len()];
        for scene in ["beam-fig2-support.toml", "my scene (2).toml", "é.toml", "t\tab.toml", "it's.toml"] {
            for (map, shard) in [(false, false), (true, false), (false, true), (true, true)] {
                let m = manifest(from, to, scene, map, shard);
                assert_eq!(m.text(), by_hand(&m), "from {from:?} to {to:?} scene {scene:?} map {map} shard {shard}");
                assert_eq!(Manifest::parse(&m.text()).unwrap(), m);
            }
        }
    }
}

/// Where the two differ, both are TOML for the same values: the toml
/// crate writes floats below 1e-4 or from 1e16 in magnitude in
/// positional notation (`0.00001`, `10000000000000000.0`: Rust's
/// `Display`, where `{:?}` wrote `1e-5`, `1e16`), and a name with `"`
/// or `\` as a literal string (`'a"b.toml'`) or a multi-line one,
/// where `{:?}` wrote Rust escapes. A folder written by hand (an older
/// version) still resumes and merges: it reads to the same manifest.
#[test]
fn where_the_texts_differ_the_values_do_not() {
    let floats = [1e-5, 2.5e-7, 3e-300, f64::MIN_POSITIVE, 1e16, 1e20, 6.02e23, -1e300, f64::MAX];
    for (k, &from) in floats.iter().enumerate() {
        let to = floats[(k + 1) % floats.len()];
        for scene in ["beam.toml", "a\"b.toml", "c:\\x\\s.toml", "it's \"x\".toml"] {
            for (map, shard) in [(false, false), (true, true)] {
                let m = manifest(from, to, scene, map, shard);
                assert_ne!(m.text(), by_hand(&m));
                for text in [m.text(), by_hand(&m)] {
                    let back = Manifest::parse(&text).unwrap();
                    assert_eq!(back, m, "{text}");
                    assert_eq!((back.from.to_bits(), back.to.to_bits()), (m.from.to_bits(), m.to.to_bits()));
                }
            }
        }
    }
}
