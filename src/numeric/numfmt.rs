//! Numbers for people: one rule for every number catflip writes into prose (messages, reports).
//!
//! ## The rule
//!
//! - A number is rounded to a number of **significant digits**: [`SIGNIFICANT`] (6) for computed
//!   results ([`num`], [`signed`]), [`ECHO_SIGNIFICANT`] (15) for values the user wrote that are
//!   echoed back ([`echo`]): 15 digits keep every digit of a decimal a person types (an `f64`
//!   holds 15 of them exactly) and drop the binary round-off of sums such as
//!   `0.2 + 0.6 + 0.3 = 1.0999999999999999`, which reads `1.1`.
//! - Trailing zeros and a trailing decimal point are dropped: `2.50000` reads `2.5`, `3.0` reads
//!   `3`.
//! - Plain decimal notation when `10⁻³ ≤ |x| < 10⁶` (`0.0012`, `123457`); scientific otherwise,
//!   with an `e` and the exponent and no `+` or leading zeros in it: `4.9985e-4`, `1e300`. The
//!   exponent is never `e0` (that range is plain).
//! - Zero is `0` (also `−0`), and non-finite values are `NaN`, `inf` and `-inf`.
//! - [`signed`] puts an explicit `+` before positive numbers (twist angles: `+7.1459`).
//!
//! Units follow the number after a space (`0.49985 ms`, `85 rad/s³`), except degrees (`+7.1459°`).
//!
//! Examples: `num(4.99850044986504e-4)` is `4.9985e-4`, `signed(7.14590000001)` is `+7.1459`,
//! `echo(1.0999999999999999)` is `1.1`, `echo(1e300)` is `1e300`, `num(1234.5678)` is `1234.57`.

/// Significant digits of a computed number in prose.
pub const SIGNIFICANT: usize = 6;

/// Significant digits of a user's value echoed back (every digit a person types; no round-off).
pub const ECHO_SIGNIFICANT: usize = 15;

/// `x` to [`SIGNIFICANT`] digits by the module's rule.
pub fn num(x: f64) -> String {
    sig(x, SIGNIFICANT)
}

/// `x` to [`SIGNIFICANT`] digits with an explicit sign (`+` for positive numbers).
pub fn signed(x: f64) -> String {
    let s = num(x);
    if x > 0.0 && x.is_finite() && s != "0" {
        format!("+{s}")
    } else {
        s
    }
}

/// A user's value echoed back: [`ECHO_SIGNIFICANT`] digits by the module's rule.
pub fn echo(x: f64) -> String {
    sig(x, ECHO_SIGNIFICANT)
}

/// `x` with `decimals` decimals (a table's fixed format) when that shows it, that is when
/// `|x| ≥ 10⁻³` or `x = 0`; smaller by the module's rule ([`num`]), so that `1e-6` does not read
/// `0.000001` or `0.0000`.
pub fn fixed(x: f64, decimals: usize) -> String {
    if x == 0.0 || x.abs() >= 1e-3 || !x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        num(x)
    }
}

/// `x` with `decimals` decimals and an explicit sign, except where it rounds to zero, which
/// reads unsigned (`0.000`, not `-0.000` for `−4e-14`).
pub fn signed_fixed(x: f64, decimals: usize) -> String {
    let shown = format!("{x:+.decimals$}");
    if shown[1..].chars().all(|c| c == '0' || c == '.') {
        shown[1..].to_string()
    } else {
        shown
    }
}

/// A relative difference `fraction` in words, `"31.2 % above"` or `"31.2 % below"` (one decimal),
/// never a negative "above".
pub fn above_or_below(fraction: f64) -> String {
    let word = if fraction < 0.0 { "below" } else { "above" };
    format!("{:.1} % {word}", 100.0 * fraction.abs())
}

/// `x` to `digits` significant digits (at least one) by the module's rule.
pub fn sig(x: f64, digits: usize) -> String {
    if x.is_nan() {
        return "NaN".to_string();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    if x == 0.0 {
        return "0".to_string();
    }
    let digits = digits.max(1);
    let sci = rounded(x, digits);
    let (mantissa, exponent) = sci.split_once('e').unwrap_or((sci.as_str(), "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let all: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let kept = all.trim_end_matches('0');
    let kept = if kept.is_empty() { "0" } else { kept };
    let sign = if x < 0.0 { "-" } else { "" };
    let body = if (-3..6).contains(&exponent) {
        plain(kept, exponent)
    } else {
        let (first, rest) = kept.split_at(1);
        if rest.is_empty() {
            format!("{first}e{exponent}")
        } else {
            format!("{first}.{rest}e{exponent}")
        }
    };
    format!("{sign}{body}")
}

/// `|x|` rounded to `digits` significant digits (at least one) in Rust's `{:e}` form,
/// "d.ddddde±x": it rounds correctly, so the exponent is the rounded number's.
fn rounded(x: f64, digits: usize) -> String {
    format!("{:.*e}", digits.max(1) - 1, x.abs())
}

/// The decimal exponent of `x` once rounded to `digits` significant digits (0.99999999 to four
/// is 1.000, exponent 0); 0 for zero and what is not finite.
pub fn rounded_exponent(x: f64, digits: usize) -> i32 {
    if x == 0.0 || !x.is_finite() {
        return 0;
    }
    rounded(x, digits).split_once('e').map_or(0, |(_, e)| e.parse().unwrap_or(0))
}

/// Plain decimal notation of the digits `d₀d₁…` times `10^exponent` (first digit non-zero, no
/// trailing zeros).
fn plain(digits: &str, exponent: i32) -> String {
    if exponent < 0 {
        let zeros = "0".repeat((-exponent - 1) as usize);
        return format!("0.{zeros}{digits}");
    }
    let int_len = exponent as usize + 1;
    if digits.len() <= int_len {
        format!("{digits}{}", "0".repeat(int_len - digits.len()))
    } else {
        format!("{}.{}", &digits[..int_len], &digits[int_len..])
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_signed_fixed_zero_has_no_sign() {
        assert_eq!([signed_fixed(-4e-14, 3), signed_fixed(4e-14, 3), signed_fixed(0.0, 2)], ["0.000", "0.000", "0.00"]);
        assert_eq!([signed_fixed(52.0138, 3), signed_fixed(-0.0006, 3)], ["+52.014", "-0.001"]);
    }

    #[test]
    fn a_relative_difference_is_never_a_negative_above() {
        assert_eq!(super::above_or_below(0.312), "31.2 % above");
        assert_eq!(super::above_or_below(-0.312), "31.2 % below");
        assert_eq!(super::above_or_below(0.0), "0.0 % above");
    }

    use super::*;

    #[test]
    fn fixed_keeps_a_table_s_decimals_unless_they_would_hide_the_number() {
        assert_eq!(fixed(0.316452, 6), "0.316452");
        assert_eq!(fixed(437.3025951, 6), "437.302595");
        assert_eq!(fixed(0.0, 4), "0.0000");
        assert_eq!(fixed(1e-3, 4), "0.0010");
        // Below 1e-3 a fixed format shows zeros or one digit: the module's rule instead.
        assert_eq!(fixed(1e-6, 6), "1e-6");
        assert_eq!(fixed(-9.99617e-7, 4), "-9.99617e-7");
    }

    #[test]
    fn the_examples_of_the_issue_read_as_people_write_them() {
        assert_eq!(num(4.99850044986504e-4), "4.9985e-4");
        assert_eq!(signed(7.1459), "+7.1459");
        assert_eq!(echo(1.0999999999999999), "1.1");
        assert_eq!(echo(1e300), "1e300");
        assert_eq!(echo(1.5e-300), "1.5e-300");
    }

    #[test]
    fn plain_between_a_thousandth_and_a_million_scientific_outside() {
        assert_eq!(num(0.001), "0.001");
        assert_eq!(num(0.00099999), "9.9999e-4");
        assert_eq!(num(999_999.0), "999999");
        assert_eq!(num(1_000_000.0), "1e6");
        assert_eq!(num(1234.5678), "1234.57");
        assert_eq!(num(-0.5), "-0.5");
        assert_eq!(num(3.0), "3");
        assert_eq!(num(120.0), "120");
        assert_eq!(num(2.5e-7), "2.5e-7");
    }

    #[test]
    fn rounding_that_carries_moves_the_exponent() {
        assert_eq!(num(9.9999996), "10");
        assert_eq!(num(999_999.6), "1e6");
        assert_eq!(num(0.00099999996), "0.001");
    }

    #[test]
    fn zero_signs_and_non_finite_values() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(-0.0), "0");
        assert_eq!(signed(0.0), "0");
        assert_eq!(signed(-2.0), "-2");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(num(f64::INFINITY), "inf");
        assert_eq!(num(f64::NEG_INFINITY), "-inf");
        assert_eq!(signed(f64::INFINITY), "inf");
    }

    #[test]
    fn echo_keeps_every_typed_digit() {
        assert_eq!(echo(0.1), "0.1");
        assert_eq!(echo(1.000000001), "1.000000001");
        assert_eq!(echo(123456.789), "123456.789");
        assert_eq!(echo(f64::MIN_POSITIVE / 4.0), "5.562684646268e-309");
    }
}
