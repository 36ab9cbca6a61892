//! How long diagnostic lists read in text: a model of hundreds of coefficients (a
//! 100-DOF chain with a dashpot per link and a damper per mass has 201) would otherwise
//! print every trade-off over every coefficient. The text keeps the few largest
//! entries and says how many more there are ("+ 40 more"); the JSON keeps everything.
//!
//! - A coefficient's **term** is its name up to the `[` of a per-element name
//!   (`dashpot[3-4]` → `dashpot`), else the whole name (a shared coefficient `c`).
//! - The **largest contributors** of a weight vector w are the k entries of largest |w_j|,
//!   ties in model order.
//! - A **decade histogram** of values x ≥ 1 counts them in [10^d, 10^(d+1)),
//!   d = ⌊log₁₀ x⌋, with the infinite ones apart.
//! - A long **sequence** (singular values) shows its first and last few.

use std::collections::BTreeMap;

/// Lists longer than this are summarised in text (coefficient tables, VIFs, singular
/// values, directions).
pub const FULL_LISTING: usize = 20;
/// Entries shown of a summarised list: the contributors of one direction.
pub const CONTRIBUTORS: usize = 5;
/// Directions or combinations listed before "+ N more".
pub const LISTED: usize = 10;

/// The term a coefficient belongs to: `dashpot[3-4]` → `dashpot`, `c` → `c`.
pub fn term_of(name: &str) -> &str {
    match name.find('[') {
        Some(i) if i > 0 => &name[..i],
        _ => name,
    }
}

/// How many of `names` belong to each term, in order of first appearance.
pub fn by_term<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<(&'a str, usize)> {
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for name in names {
        let term = term_of(name);
        match counts.iter_mut().find(|(t, _)| *t == term) {
            Some((_, n)) => *n += 1,
            None => counts.push((term, 1)),
        }
    }
    counts
}

/// `dashpot 23, quad 22`.
pub fn by_term_text<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    by_term(names)
        .iter()
        .map(|(t, n)| format!("{t} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Indices of the `k` entries of largest magnitude, largest first (ties in index order).
pub fn largest(weights: &[f64], k: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..weights.len()).collect();
    order.sort_by(|&a, &b| {
        weights[b]
            .abs()
            .total_cmp(&weights[a].abs())
            .then(a.cmp(&b))
    });
    order.truncate(k);
    order
}

/// Counts per decade of the finite values (`(d, count)` for [10^d, 10^(d+1)), values
/// below 1 counted in decade 0) and the number of infinite ones (`None`).
pub fn decade_histogram(values: &[Option<f64>]) -> (Vec<(i32, usize)>, usize) {
    let mut decades: BTreeMap<i32, usize> = BTreeMap::new();
    let mut infinite = 0;
    for v in values {
        match v {
            Some(x) if x.is_finite() => {
                *decades
                    .entry(x.max(1.0).log10().floor() as i32)
                    .or_default() += 1;
            }
            _ => infinite += 1,
        }
    }
    (decades.into_iter().collect(), infinite)
}

/// `1e2–1e3: 4, 1e3–1e4: 7, infinite: 2`.
pub fn decade_histogram_text(values: &[Option<f64>]) -> String {
    let (decades, infinite) = decade_histogram(values);
    let mut parts: Vec<String> = decades
        .iter()
        .map(|(d, n)| format!("1e{d}–1e{}: {n}", d + 1))
        .collect();
    if infinite > 0 {
        parts.push(format!("infinite: {infinite}"));
    }
    parts.join(", ")
}

/// `[a, b, c]` with `{:.3e}` entries; longer than [`FULL_LISTING`]: the first five and the
/// last two, `[a, b, c, d, e, …, y, z] (201 values)`.
pub fn sequence(values: &[f64]) -> String {
    let show = |s: &[f64]| {
        s.iter()
            .map(|x| format!("{x:.3e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if values.len() <= FULL_LISTING {
        format!("[{}]", show(values))
    } else {
        format!(
            "[{}, …, {}] ({} values)",
            show(&values[..5]),
            show(&values[values.len() - 2..]),
            values.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terms_and_largest() {
        assert_eq!(term_of("dashpot[3-4]"), "dashpot");
        assert_eq!(term_of("c"), "c");
        assert_eq!(term_of("[odd]"), "[odd]");
        assert_eq!(
            by_term(["a[1]", "b", "a[2]", "a[3]"]),
            vec![("a", 3), ("b", 1)]
        );
        // |w| = 0.1, 3, 2, 3: the two 3s in index order, then 2.
        assert_eq!(largest(&[0.1, -3.0, 2.0, 3.0], 3), vec![1, 3, 2]);
        assert_eq!(largest(&[1.0], 5), vec![0]);
    }

    #[test]
    fn histogram_counts_every_value_once() {
        let values = [
            Some(1.0),
            Some(9.99),
            Some(10.0),
            Some(2e5),
            None,
            Some(0.5),
        ];
        let (decades, infinite) = decade_histogram(&values);
        assert_eq!(decades, vec![(0, 3), (1, 1), (5, 1)]);
        assert_eq!(infinite, 1);
        assert_eq!(
            decade_histogram_text(&values),
            "1e0–1e1: 3, 1e1–1e2: 1, 1e5–1e6: 1, infinite: 1"
        );
    }

    #[test]
    fn long_sequences_are_cut() {
        let short: Vec<f64> = (1..=3).map(f64::from).collect();
        assert_eq!(sequence(&short), "[1.000e0, 2.000e0, 3.000e0]");
        let long: Vec<f64> = (1..=30).map(f64::from).collect();
        let text = sequence(&long);
        assert_eq!(
            text,
            "[1.000e0, 2.000e0, 3.000e0, 4.000e0, 5.000e0, …, 2.900e1, 3.000e1] (30 values)"
        );
    }
}
