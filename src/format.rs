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
//! Tables in reports keep their own fixed formats.

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
}
