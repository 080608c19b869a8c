//! A measured wind field from CSV: header `time_s,x_m,u_m_s,w_m_s`, one line per time and deck
//! point, the turbulence `u` (along wind) and `w` (vertical, + up) about the mean speed given
//! separately. Times ascend with a constant step; every time carries the same points in
//! ascending `x`. Blank lines and lines starting with `#` are skipped. Beyond its ends the
//! record holds its end values.

use crate::field::{check_points, WindField};
use crate::WindError;

/// The expected header.
pub const HEADER: &str = "time_s,x_m,u_m_s,w_m_s";

/// The largest turbulence a record may give, |u| and |w|, m/s: beyond any measured gust
/// (a value past it is a unit or column mistake, not wind).
pub const MAX_TURBULENCE_M_S: f64 = 100.0;

/// The rows of one time: (time, line of its first row, points, u, w).
type Block = (f64, usize, Vec<f64>, Vec<f64>, Vec<f64>);

/// Parse a record named `file` in messages; `mean_speed_m_s` is the mean wind U (m/s, ≥ 0).
pub fn parse(text: &str, file: &str, mean_speed_m_s: f64) -> Result<WindField, WindError> {
    let at = |line: usize, problem: String| WindError::RecordLine {
        file: file.into(),
        line,
        problem,
    };
    let whole = |problem: String| WindError::RecordFile {
        file: file.into(),
        problem,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    match lines.next() {
        Some((_, h)) if h.replace(' ', "") == HEADER => {}
        Some((i, h)) => return Err(at(i, format!("the header is `{h}`, expected `{HEADER}`"))),
        None => return Err(whole(format!("empty; expected the header {HEADER}"))),
    }
    let mut blocks: Vec<Block> = Vec::new();
    for (i, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 4 {
            return Err(at(
                i,
                format!("`{line}` has {} fields, expected {HEADER}", fields.len()),
            ));
        }
        let mut v = [0.0; 4];
        for (k, (name, s)) in HEADER.split(',').zip(&fields).enumerate() {
            v[k] = s
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| at(i, format!("{name} `{s}` is not a finite number")))?;
        }
        let [t, x, u, w] = v;
        for (name, value, written) in [("u_m_s", u, fields[2]), ("w_m_s", w, fields[3])] {
            if value.abs() > MAX_TURBULENCE_M_S {
                return Err(at(
                    i,
                    format!(
                        "{name} = {written} is beyond ±{MAX_TURBULENCE_M_S} m/s: turbulence about the mean, in m/s"
                    ),
                ));
            }
        }
        match blocks.last_mut() {
            Some(b) if b.0 == t => {
                if x <= *b.2.last().expect("a point") {
                    return Err(at(
                        i,
                        format!("x_m = {x} does not ascend within time {t} s"),
                    ));
                }
                b.2.push(x);
                b.3.push(u);
                b.4.push(w);
            }
            Some(b) if t < b.0 => {
                return Err(at(
                    i,
                    format!("time_s = {t} is before the previous time {} s", b.0),
                ));
            }
            _ => blocks.push((t, i, vec![x], vec![u], vec![w])),
        }
        if blocks.len() * blocks[0].2.len() > crate::field::MAX_SAMPLES / 2 {
            return Err(at(i, "the record is too large".into()));
        }
    }
    let Some(first) = blocks.first() else {
        return Err(whole("no data after the header".into()));
    };
    let points = first.2.clone();
    check_points(&points).map_err(|e| whole(e.to_string()))?;
    for b in &blocks[1..] {
        if b.2 != points {
            let missing: Vec<String> = points
                .iter()
                .filter(|x| !b.2.contains(x))
                .map(|x| format!("{x}"))
                .collect();
            return Err(at(
                b.1,
                if missing.is_empty() {
                    format!(
                        "time {} s has points {:?}, the first time has {:?}",
                        b.0, b.2, points
                    )
                } else {
                    format!(
                        "time {} s misses the points x_m = {}",
                        b.0,
                        missing.join(", ")
                    )
                },
            ));
        }
    }
    let dt = if blocks.len() > 1 {
        blocks[1].0 - blocks[0].0
    } else {
        1.0
    };
    for (k, b) in blocks.iter().enumerate() {
        let expected = blocks[0].0 + k as f64 * dt;
        if (b.0 - expected).abs() > 1e-9 * dt.max(b.0.abs()) {
            return Err(at(
                b.1,
                format!(
                    "time_s = {} breaks the constant step {dt} s (expected {expected})",
                    b.0
                ),
            ));
        }
    }
    if !(mean_speed_m_s.is_finite() && mean_speed_m_s >= 0.0) {
        return Err(WindError::invalid(
            "mean_speed_m_s",
            mean_speed_m_s,
            "must be ≥ 0",
        ));
    }
    let np = points.len();
    let series = |pick: fn(&Block) -> &Vec<f64>| {
        (0..np)
            .map(|j| blocks.iter().map(|b| pick(b)[j]).collect())
            .collect()
    };
    Ok(WindField {
        mean_speed_m_s,
        x_m: points,
        t0_s: blocks[0].0,
        dt_s: dt,
        u: series(|b| &b.3),
        w: series(|b| &b.4),
        periodic: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "time_s,x_m,u_m_s,w_m_s\n0,0,1,0.5\n0,10,2,0.25\n0.5,0,3,0\n0.5,10,4,-1\n";

    #[test]
    fn a_record_reads_and_interpolates() {
        let f = parse(GOOD, "w.csv", 20.0).unwrap();
        assert_eq!(f.x_m, vec![0.0, 10.0]);
        assert_eq!(f.at(0.0, 0.0), [1.0, 0.5]);
        assert_eq!(f.at(5.0, 0.25), [2.5, -0.0625]);
        assert_eq!(f.at(10.0, 99.0), [4.0, -1.0], "held beyond the end");
        assert_eq!(f.at(-3.0, -1.0), [1.0, 0.5], "held before the start");
    }

    #[test]
    fn bad_records_are_refused_by_line() {
        let cases = [
            ("", "empty"),
            ("t,x,u,w\n", "the header is `t,x,u,w`"),
            ("time_s,x_m,u_m_s,w_m_s\n", "no data"),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1\n",
                "w.csv:2: `0,0,1` has 3 fields",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1,x\n",
                "w.csv:2: w_m_s `x` is not a finite number",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1,0\n0,10,1,0\n0.5,0,1,0\n1,0,1,0\n1,10,1,0\n",
                "w.csv:4: time 0.5 s misses the points x_m = 10",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1,0\n0.5,0,1,0\n1.5,0,1,0\n",
                "w.csv:4: time_s = 1.5 breaks the constant step 0.5 s",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n1,0,1,0\n0,0,1,0\n",
                "w.csv:3: time_s = 0 is before",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,5,1,0\n0,5,1,0\n",
                "w.csv:3: x_m = 5 does not ascend",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1,0\n0,5,1e300,0\n",
                "w.csv:3: u_m_s = 1e300 is beyond ±100 m/s",
            ),
            (
                "time_s,x_m,u_m_s,w_m_s\n0,0,1,-101\n",
                "w.csv:2: w_m_s = -101 is beyond ±100 m/s",
            ),
        ];
        for (text, needle) in cases {
            let e = parse(text, "w.csv", 20.0).unwrap_err().to_string();
            assert!(e.contains(needle), "{needle:?} not in {e:?}");
        }
        assert!(parse(GOOD, "w.csv", -1.0)
            .unwrap_err()
            .to_string()
            .contains("mean_speed_m_s = -1"));
    }
}
