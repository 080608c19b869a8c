//! How far two runs of one scenario are apart, column by column of their histories:
//! `max_t |co − mono| / max_t |mono|` (the monolithic run is the reference; a column that is
//! zero there and not in the co-simulation counts as infinitely different).

use crate::output::plots::History;

/// The difference of one column.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ColumnDifference {
    pub column: String,
    /// `max |co − mono| / max |mono|`.
    pub relative: f64,
    /// Time of the largest `|co − mono|`, s.
    pub time_s: f64,
}

/// Differences of every column (but time) of two histories with the same columns and rows.
pub fn differences(mono: &History, co: &History) -> Result<Vec<ColumnDifference>, String> {
    if mono.names != co.names {
        return Err("the two histories have different columns".into());
    }
    let t = mono.column("time_s").ok_or("history without time_s")?;
    let mut out = Vec::new();
    for (j, name) in mono.names.iter().enumerate() {
        if name == "time_s" {
            continue;
        }
        let (a, b) = (&mono.columns[j], &co.columns[j]);
        if a.len() != b.len() {
            return Err(format!("{name}: {} rows against {}", a.len(), b.len()));
        }
        let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let (mut worst, mut at) = (0.0_f64, t.first().copied().unwrap_or(0.0));
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            let d = (x - y).abs();
            if d.is_nan() || d > worst {
                worst = if d.is_nan() { f64::INFINITY } else { d };
                at = t[k];
            }
        }
        let relative = if scale > 0.0 {
            worst / scale
        } else if worst == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        out.push(ColumnDifference {
            column: name.clone(),
            relative,
            time_s: at,
        });
    }
    Ok(out)
}
