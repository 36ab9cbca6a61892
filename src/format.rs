//! How numbers appear in messages: one helper for every error and warning text.
//!
//! ```text
//!   number(x) = shortest decimal that reads back as x,   1e-4 ≤ |x| < 1e6 or x = 0
//!             = the same digits in scientific notation,  otherwise
//!   integer(n) = n,                                      n < 10⁶
//!              = 4 significant digits, scientific,       otherwise
//! ```
//!
//! so 1e300 prints as `1e300`, not 301 digits, and a saturated count as `1.845e19`.
//! Tables in reports keep their own fixed formats. Labels (a unit, a plot's title or
//! legend) round to four significant digits:
//!
//! ```text
//!   label(x) = x to 4 significant digits, trailing zeros dropped,   1e-3 ≤ |x| < 1e5 or x = 0
//!            = the same in scientific notation,                      otherwise
//! ```
//!
//! so an estimated exponent reads `N·(s/m)^2.612`, not `N·(s/m)^2.611665943989249`;
//! [`labels_in`] rounds every number of a text so (a law's name, `power(2.612)`).

/// `x` in the shortest form that reads back as `x` (module doc).
pub fn number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A count (samples, steps, bytes): exact below 10⁶, else 4 significant digits.
pub fn integer(n: impl Into<u128>) -> String {
    let n: u128 = n.into();
    if n < 1_000_000 {
        n.to_string()
    } else {
        format!("{:.3e}", n as f64)
    }
}

/// `text` with every control character (C0, DEL, C1: ESC of an ANSI sequence, BEL, CR,
/// newline, tab) and every bidirectional override written as its escape `\u{1b}`, so a
/// title or label from a file prints as one line of inert text on a terminal.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    let inert = |c: char| {
        !(c.is_control()
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c))
    };
    if text.chars().all(inert) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut clean = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if inert(c) {
            clean.push(c);
        } else {
            clean.push_str(&c.escape_unicode().to_string());
        }
    }
    std::borrow::Cow::Owned(clean)
}

/// Significant digits of a number in a label.
const LABEL_DIGITS: i32 = 4;

/// `x` rounded for a label (module doc).
pub fn label(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let trim = |text: String| -> String {
        match text.split_once('e') {
            Some((mantissa, exponent)) if mantissa.contains('.') => format!(
                "{}e{exponent}",
                mantissa.trim_end_matches('0').trim_end_matches('.')
            ),
            Some(_) => text,
            None if text.contains('.') => {
                text.trim_end_matches('0').trim_end_matches('.').to_string()
            }
            None => text,
        }
    };
    let magnitude = x.abs();
    if (1e-3..1e5).contains(&magnitude) {
        // Decimals for 4 significant digits, after rounding (9.9996 → 10.00).
        let mut decimals = LABEL_DIGITS - 1 - magnitude.log10().floor() as i32;
        let rounded = format!("{x:.prec$}", prec = decimals.max(0) as usize);
        if rounded.trim_start_matches('-').starts_with("10") && decimals > 0 {
            let shown: f64 = rounded.parse().unwrap_or(x);
            decimals = LABEL_DIGITS - 1 - shown.abs().log10().floor() as i32;
        }
        trim(format!("{x:.prec$}", prec = decimals.max(0) as usize))
    } else {
        trim(format!("{x:.prec$e}", prec = (LABEL_DIGITS - 1) as usize))
    }
}

/// `text` with every number of more than four significant digits rounded by [`label`]
/// (a number is a run of digits with an optional fraction and exponent that does not
/// continue a name, as the `1` of `x1` does).
pub fn labels_in(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit()
            && !(i > 0
                && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_' || chars[i - 1] == '.'));
        if !starts {
            out.push(chars[i]);
            i += 1;
            continue;
        }
        let mut j = i;
        while j < chars.len() && chars[j].is_ascii_digit() {
            j += 1;
        }
        if j + 1 < chars.len() && chars[j] == '.' && chars[j + 1].is_ascii_digit() {
            j += 1;
            while j < chars.len() && chars[j].is_ascii_digit() {
                j += 1;
            }
        }
        if j < chars.len() && (chars[j] == 'e' || chars[j] == 'E') {
            let mut k = j + 1;
            if k < chars.len() && (chars[k] == '-' || chars[k] == '+') {
                k += 1;
            }
            if k < chars.len() && chars[k].is_ascii_digit() {
                while k < chars.len() && chars[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        let token: String = chars[i..j].iter().collect();
        let mantissa = token.split(['e', 'E']).next().unwrap_or("");
        let significant = mantissa
            .trim_start_matches(['0', '.'])
            .chars()
            .filter(char::is_ascii_digit)
            .count();
        match token.parse::<f64>() {
            Ok(x) if significant > LABEL_DIGITS as usize => out.push_str(&label(x)),
            _ => out.push_str(&token),
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_from_files_prints_inert() {
        assert_eq!(
            printable("Four-mass chain (ω = 0.618)"),
            "Four-mass chain (ω = 0.618)"
        );
        assert_eq!(
            printable("\u{1b}[31mred\u{7}\r\n"),
            "\\u{1b}[31mred\\u{7}\\u{d}\\u{a}"
        );
        assert_eq!(printable("a\u{202e}b\u{85}"), "a\\u{202e}b\\u{85}");
    }

    #[test]
    fn numbers_are_short_and_round_trip() {
        assert_eq!(number(0.25), "0.25");
        assert_eq!(number(123456.5), "123456.5");
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-2.5e-7), "-2.5e-7");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::INFINITY), "inf");
        for x in [0.1 + 0.2, 1.0 / 3.0, 9.9991125876e-1, 6.9e-311, f64::MAX] {
            assert_eq!(number(x).parse::<f64>().unwrap(), x);
        }
    }

    /// Messages use it: a huge parameter is one short number, a saturated sample count
    /// four digits.
    #[test]
    fn messages_are_readable() {
        let huge = crate::Error::invalid("period", 6.4e288, "too long").to_string();
        assert_eq!(huge, "invalid period = 6.4e288: too long");
        let short = crate::Error::RecordTooShort {
            record: "r".into(),
            needed: usize::MAX,
            available: 512,
        }
        .to_string();
        assert!(
            short.contains("need 1.845e19 samples, it has 512"),
            "{short}"
        );
    }

    #[test]
    fn counts_stay_readable() {
        assert_eq!(integer(512u32), "512");
        assert_eq!(integer(usize::MAX as u64), "1.845e19");
    }

    /// Labels carry four significant digits, no trailing zeros, and exponent form
    /// outside [1e-3, 1e5).
    #[test]
    fn labels_are_rounded() {
        assert_eq!(label(2.611665943989249), "2.612");
        assert_eq!(label(1.5), "1.5");
        assert_eq!(label(2.0), "2");
        assert_eq!(label(-0.000123456), "-1.235e-4");
        assert_eq!(label(12345.678), "12346");
        assert_eq!(label(9.99996), "10");
        assert_eq!(label(0.00123456), "0.001235");
        assert_eq!(label(1.0e7), "1e7");
        assert_eq!(label(0.0), "0");
        for x in [2.611665943989249, 0.000123456, 98696.04401, 3.14159e-9] {
            let back: f64 = label(x).parse().unwrap();
            assert!((back - x).abs() <= 5e-4 * x.abs(), "{x} → {back}");
        }
    }

    /// Numbers in a text are rounded; short ones, names with digits and the text
    /// around them stay.
    #[test]
    fn numbers_in_labels_are_rounded() {
        assert_eq!(labels_in("power(2.611665943989249)"), "power(2.612)");
        assert_eq!(labels_in("N·(s/m)^2.611665943989249"), "N·(s/m)^2.612");
        assert_eq!(labels_in("power(1.5) law"), "power(1.5) law");
        assert_eq!(
            labels_in("x1*abs(v)^1.23456e-3 + 12"),
            "x1*abs(v)^0.001235 + 12"
        );
        assert_eq!(labels_in("sign(v)*abs(v)^1.5"), "sign(v)*abs(v)^1.5");
        assert_eq!(labels_in("dashpot[2-3]"), "dashpot[2-3]");
        assert_eq!(labels_in("ω = 314.15926"), "ω = 314.2");
    }
}
