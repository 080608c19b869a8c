//! The speeds (and wind speeds) of a sweep: lists and `start:stop:step` ranges, and the
//! defaults of the paper and of EN 1991-2 §6.4.6.

use super::table2::PAPER_SPEEDS;
use super::SweepOptions;

/// The speeds of `--speeds`: numbers, or `start:stop:step` ranges (stop included when it
/// is a whole number of steps from the start, to 1e-9 of a step); a speed given twice is
/// refused.
pub fn parse_speeds(items: &[String]) -> Result<Vec<f64>, String> {
    parse_range(items, "--speeds", "km/h")
}

/// Values of option `flag` (in `unit`): comma-separated items, each a number or
/// `start:stop:step` (stop included); each value once.
pub fn parse_range(items: &[String], flag: &str, unit: &str) -> Result<Vec<f64>, String> {
    let number = |t: &str| -> Result<f64, String> {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{flag}: \"{}\" is not a number", t.trim()))
    };
    let mut speeds = Vec::new();
    for item in items {
        let parts: Vec<&str> = item.split(':').collect();
        match parts.as_slice() {
            [v] => speeds.push(number(v)?),
            [a, b, c] => {
                let (start, stop, step) = (number(a)?, number(b)?, number(c)?);
                if step <= 0.0 || stop < start {
                    return Err(format!(
                        "{flag} {item}: expected start:stop:step with stop ≥ start and step > 0"
                    ));
                }
                let n = ((stop - start) / step + 1e-9).floor();
                if n > 100_000.0 {
                    return Err(format!("{flag} {item}: {n} values, more than 100000"));
                }
                speeds.extend((0..=n as usize).map(|k| start + k as f64 * step));
            }
            _ => {
                return Err(format!(
                    "{flag} {item}: expected a number or start:stop:step"
                ))
            }
        }
    }
    if speeds.is_empty() {
        return Err(format!("{flag}: give at least one value"));
    }
    for (i, v) in speeds.iter().enumerate() {
        if speeds[..i].contains(v) {
            return Err(format!(
                "{flag}: {} {unit} is given twice",
                crate::text::num(*v)
            ));
        }
    }
    Ok(speeds)
}

/// The speeds of a sweep: `--speeds`, or by default the paper's four, or with `--trains`
/// EN 1991-2 §6.4.6's 40 m/s (144 km/h) to 1.2 × the scenario's speed in 2.5 km/h steps.
pub fn of(
    args: &SweepOptions,
    base: &crate::scenario::Scenario,
) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    Ok(match (args.speeds.is_empty(), args.trains.is_empty()) {
        (false, _) => parse_speeds(&args.speeds)?,
        (true, true) => PAPER_SPEEDS.to_vec(),
        (true, false) => {
            let top = 1.2 * base.run.speed_kmh;
            if top < 144.0 {
                return Err(format!(
                    "--speeds: the default range 144 km/h to 1.2 × the scenario's {} km/h is empty; give --speeds",
                    crate::text::num(base.run.speed_kmh)
                )
                .into());
            }
            parse_speeds(&[format!("144:{top}:2.5")])?
        }
    })
}
