//! A faer matrix as serde sees it: its shape, then its entries column by column
//! (`{"rows": m, "columns": n, "entries": [A_00, A_10, …]}`), so that a regressor built
//! on one machine is the same bits on another (`#[serde(with = "serde_mat")]`).

use faer::Mat;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

#[derive(Serialize, Deserialize)]
struct Stored {
    rows: usize,
    columns: usize,
    entries: Vec<f64>,
}

pub(crate) fn serialize<S: Serializer>(
    matrix: &Mat<f64>,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    let entries = (0..matrix.ncols())
        .flat_map(|k| (0..matrix.nrows()).map(move |r| matrix[(r, k)]))
        .collect();
    Stored {
        rows: matrix.nrows(),
        columns: matrix.ncols(),
        entries,
    }
    .serialize(serializer)
}

pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Mat<f64>, D::Error> {
    let stored = Stored::deserialize(deserializer)?;
    if stored.rows.checked_mul(stored.columns) != Some(stored.entries.len()) {
        return Err(D::Error::custom(format!(
            "a {} × {} matrix needs {} entries, not {}",
            stored.rows,
            stored.columns,
            stored.rows.saturating_mul(stored.columns),
            stored.entries.len()
        )));
    }
    let rows = stored.rows;
    Ok(Mat::from_fn(rows, stored.columns, |r, k| {
        stored.entries[k * rows + r]
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize, Deserialize)]
    struct Holder(#[serde(with = "super")] Mat<f64>);

    /// A 2 × 3 matrix survives a round trip through JSON bit for bit; a wrong entry
    /// count is an error, not a panic.
    #[test]
    fn round_trip_and_shape_check() {
        let a = Mat::from_fn(2, 3, |r, k| r as f64 * 0.5 - k as f64 * 0.25);
        let text = serde_json::to_string(&Holder(a.clone())).unwrap();
        let back: Holder = serde_json::from_str(&text).unwrap();
        assert_eq!(back.0, a);
        let bad = r#"{"rows": 2, "columns": 3, "entries": [1.0]}"#;
        let err = serde_json::from_str::<Holder>(bad).err().unwrap();
        assert!(err.to_string().contains("needs 6 entries"), "{err}");
    }
}
