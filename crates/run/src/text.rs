//! Numbers in messages: Rust prints an `f64` in its shortest round-trip
//! digits but never with an exponent, so 1e300 becomes a 301-digit decimal.
//! [`num`] prints very large and very small numbers with an exponent;
//! [`tidy_numbers`] rewrites such decimals inside a finished message (every
//! front end passes its error messages through it), losslessly: the digits
//! Rust printed are the shortest that round-trip, and so are `{:e}`'s.

/// `x` in its shortest round-trip form, with an exponent when |x| >= 1e16
/// or 0 < |x| < 1e-5 (`1e300`, `2.5e-12`; `0.1`, `640` as they are).
pub fn num(x: f64) -> String {
    let a = x.abs();
    if x.is_finite() && a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The longest plain decimal left as it is (characters): 1e16 prints as
/// 17 digits, 1e-5 as `0.00001`.
const LONGEST_PLAIN: usize = 17;

/// Digits of the largest 64-bit integer (`u64::MAX`): a longer integer is
/// a printed `f64`.
const MAX_INTEGER_DIGITS: usize = 20;

/// `msg` with every plain decimal longer than 17 characters (as Rust prints
/// numbers >= 1e17 or with many leading zeros) rewritten in the exponent
/// form of [`num`], except integers of up to 20 digits (a count the user
/// typed, e.g. 2^63 - 1, stays exact); everything else is kept byte for byte.
pub fn tidy_numbers(msg: &str) -> String {
    let b = msg.as_bytes();
    let mut out = String::with_capacity(msg.len());
    let mut i = 0;
    while i < b.len() {
        // A numeral starts with a digit that does not continue a word.
        if b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'.' || b[i - 1] == b'_')) {
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                j += 1;
            }
            // Not the mantissa of an exponent form, nor part of a word.
            let followed = j < b.len() && (b[j].is_ascii_alphabetic() || b[j] == b'_');
            let token = &msg[i..j];
            let token = token.strip_suffix('.').unwrap_or(token);
            let end = i + token.len();
            match token.parse::<f64>() {
                // An integer of up to 20 digits may be a count the user typed (u64): kept exactly.
                Ok(v) if token.len() > LONGEST_PLAIN && (token.contains('.') || token.len() > MAX_INTEGER_DIGITS) && !followed && token.matches('.').count() <= 1 && v.is_finite() => {
                    out.push_str(&num(v))
                }
                _ => out.push_str(token),
            }
            i = end;
        } else {
            let c = msg[i..].chars().next().expect("i is on a char boundary");
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}
