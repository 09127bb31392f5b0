//! The tests of `signorini_run::text` that were unit tests in src/text.rs (the
//! library is not compiled a second time as a test harness).

use signorini_run::text::*;

#[test]
fn huge_and_tiny_decimals_get_an_exponent_and_nothing_else_changes() {
    let big = format!("1{}", "0".repeat(300));
    let tiny = format!("0.{}1", "0".repeat(299));
    let odd = format!("0.{}29999999999999996", "0".repeat(299));
    assert_eq!(tidy_numbers(&format!("dt = {big} (T/dt = {odd}): ends at {big}.")), "dt = 1e300 (T/dt = 2.9999999999999996e-300): ends at 1e300.");
    assert_eq!(tidy_numbers(&format!("bar.dt: {tiny} gives 3.000e300 steps")), "bar.dt: 1e-300 gives 3.000e300 steps");
    assert_eq!(tidy_numbers(&format!("-{big}")), "-1e300");
    for plain in ["dt = 0.05, 640 elements, 1e9 steps, 1.2.3, x2, t = 0.42", "12345678901234567 is 17 digits", "elements = 9223372036854775807 and 18446744073709551615", "ümlaut 3 → 4", "0.00001"]
    {
        assert_eq!(tidy_numbers(plain), plain);
    }
    // Checked against the numbers themselves, not the function's own output.
    assert_eq!(big.to_string().parse::<f64>().unwrap(), 1e300);
    assert_eq!(num(1e300), "1e300");
    assert_eq!(num(-2.5e-12), "-2.5e-12");
    assert_eq!(num(0.1), "0.1");
    assert_eq!(num(640.0), "640");
    assert_eq!(num(f64::NAN), "NaN");
}
