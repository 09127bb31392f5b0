//! The unit tests of `crates/exact/src/dirichlet.rs` (its private `rem3`
//! and `phase`, `#[doc(hidden)] pub` for them), moved unchanged: the
//! library is not compiled a second time as a test harness.
/// `rem3` is `rem_euclid(3.0)` bit for bit, and the phase the one
/// `rem_euclid` and `floor` give: at the levels `n dt` of the
/// runs (the studies' `dt`), at and around multiples of the period
/// (the quotient's rounding), below and at the fast path's bounds, for
/// signed zeros, negative, huge and non-finite `t`.
#[test]
fn rem3_is_rem_euclid_bit_for_bit() {
    let mut ts = vec![0.0, -0.0, 1e-300, 5e-324, -1e-300, -2.5, -3.0, 1.5, 3.0, 6.0, 9.0, 2.0_f64.powi(48), 2.0_f64.powi(48) - 1.0, 1e17, f64::MAX, f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
    for dt in [1e-2, 1e-3, 1.0 / 3.0, 1.0 / 640.0, 1.0 / 1280.0 / 10.0, 3.0 / 7.0, 0.1, 1e-6] {
        ts.extend((0..20_000).map(|n| n as f64 * dt));
    }
    for j in 0..2000u32 {
        let p = 3.0 * f64::from(j) * (1.0 + f64::from(j % 7) * 1e3);
        let mut x = p;
        for _ in 0..4 {
            x = f64::from_bits(x.to_bits() - 1);
            ts.push(x);
        }
        x = p;
        for _ in 0..4 {
            ts.push(x);
            x = f64::from_bits(x.to_bits() + 1);
        }
    }
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for _ in 0..200_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        // Uniform bits of t in [2⁻¹⁰, 2⁵⁰).
        let e = (state % 60) as i32 - 10;
        let mant = f64::from_bits(0x3ff0_0000_0000_0000 | (state >> 12));
        ts.push(mant * 2.0_f64.powi(e));
    }
    // The phase as it was computed with the library's rem_euclid and floor.
    let reference = |t: f64| -> Option<(u8, u64)> {
        if !t.is_finite() {
            return None;
        }
        let tp = t.rem_euclid(3.0);
        let p = tp.floor();
        Some(if p >= 3.0 { (0, 0) } else { (p as u8, (tp - p).to_bits()) })
    };
    for t in ts {
        let (a, b) = (signorini_exact::rem3(t), t.rem_euclid(3.0));
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "t = {t:e}: {a:e} vs rem_euclid {b:e}");
        assert_eq!(signorini_exact::phase(t).map(|(p, tau)| (p, tau.to_bits())), reference(t), "phase at t = {t:e}");
    }
}
