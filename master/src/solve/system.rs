//! An SSP system run by the coupling library: the communication steps from the start to the
//! stop time, the recorded outputs streamed as CSV rows, and the coupling statistics and
//! residuals that go into the side-car.
//!
//! Step `k` (1-based) of `n` spans `[start + (k − 1) h, min(start + k h, stop)]`; a row is
//! written after initialisation, every `every` steps and after the last step.

use std::io::Write as _;
use tbi_coupling::{
    advance_into, build_scheme, CouplingConfig, CouplingStatistics, Discrete, SchemeKind, System,
};

/// One recorded column: its header, the participant, the value reference, and the kind of
/// an Integer/Boolean output (`None` for a Real).
pub type Column = (String, usize, u32, Option<Discrete>);

/// `(start, stop, h, steps, every)`: the run's start and stop times (s), its communication
/// step (s), its number of steps and the steps per result row.
pub type Times = (f64, f64, f64, usize, usize);

/// The connections an explicit scheme lags by one step, counted per pair of components:
/// Jacobi lags every connection; Gauss–Seidel (components stepped in SSD order) lags those
/// from a component to itself or to one stepped before it, the connections that close a
/// cycle of the connection graph; the implicit scheme iterates them all, lagging none.
pub fn lagged_connections(
    sys: &System,
    scheme: SchemeKind,
    components: &[tbi_ssp::Component],
) -> Vec<serde_json::Value> {
    let pairs = sys
        .connections
        .iter()
        .map(|c| (c.from, c.to))
        .chain(sys.discrete.iter().map(|c| (c.from, c.to)));
    let mut counts: Vec<((usize, usize), usize)> = Vec::new();
    for (from, to) in pairs {
        let lagged = match scheme {
            SchemeKind::Jacobi => true,
            SchemeKind::GaussSeidel => from >= to,
            SchemeKind::Implicit => false,
        };
        if !lagged {
            continue;
        }
        match counts.iter_mut().find(|(p, _)| *p == (from, to)) {
            Some((_, n)) => *n += 1,
            None => counts.push(((from, to), 1)),
        }
    }
    counts
        .into_iter()
        .map(|((from, to), n)| {
            serde_json::json!({
                "from": components[from].name,
                "to": components[to].name,
                "connections": n,
            })
        })
        .collect()
}

/// How the side-car's residuals are measured.
pub const RESIDUAL_MEASURE: &str = "weighted RMS of the change of the exchanged values in a step's last sweep (implicit) or of the defect between the lagged inputs and the outputs they stand for (explicit), each value over rtol·max|value of its group| + atol: 1 is the tolerance; the relative figure is that times rtol";

/// Initialise the coupling, then step from `start` to `stop` by `h`, writing a row after
/// initialisation and every `every` steps (and after the last) into `csv`.
pub fn step_and_record(
    sys: &mut System,
    columns: &[Column],
    cfg: &CouplingConfig,
    (start, stop, h, steps, every): Times,
    csv: &mut crate::output::outdir::NamedFile,
    quiet: bool,
) -> Result<CouplingStatistics, Box<dyn std::error::Error>> {
    let header: Vec<&str> = std::iter::once("time")
        .chain(columns.iter().map(|c| c.0.as_str()))
        .collect();
    writeln!(csv, "{}", header.join(","))?;
    let mut rows = Rows::new(columns, sys.participants.len());
    let mut scheme = build_scheme(cfg)?;
    scheme.initialize(sys)?;
    rows.write(sys, start, csv)?;
    let mut stats = CouplingStatistics::new();
    let mut report = tbi_coupling::AdvanceReport::default();
    let pb = crate::output::progress::bar(steps, !quiet);
    for k in 1..=steps {
        let (t, t1, hk) = communication_step(start, stop, h, k, steps);
        crate::interrupt::check(t)?;
        advance_into(scheme.as_mut(), sys, t, hk, cfg.policy(hk), &mut report)
            .map_err(|e| format!("co-simulation stopped at t = {t} s: {e}"))?;
        stats.record(&report);
        if k.is_multiple_of(every) || k == steps {
            rows.write(sys, t1, csv)?;
        }
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(stats)
}

/// The steps per result row of `--output-interval dt` with step size `h`: `dt / h`, which must
/// be a positive whole number (to 1e-9 of it).
pub fn steps_per_row(dt: f64, h: f64) -> Result<usize, String> {
    let ratio = dt / h;
    let whole = ratio.round();
    if !(dt.is_finite() && dt > 0.0 && whole >= 1.0 && (ratio - whole).abs() <= 1e-9 * whole) {
        return Err(format!(
            "--output-interval {dt}: must be a positive whole multiple of the step size {h} s"
        ));
    }
    if whole > 1e9 {
        return Err(format!(
            "--output-interval {dt}: more than 1e9 steps of {h} s between rows"
        ));
    }
    Ok(whole as usize)
}

/// Step `k` (1-based) of `steps`: its start `t = start + (k − 1) h`, its end `t₁` and its size.
///
/// The size is the nominal `h` itself, not `t₁ − t`: that difference jitters with the
/// rounding of `t` (by about 1e-11 of h at t = 100 s with h = 2 ms), so every FMU would see a
/// new step size in every step and redo what it keeps per step size (and the iteration then
/// takes more sweeps). Only a last step that ends at `stop` more than round-off short of a
/// whole step is shorter.
fn communication_step(start: f64, stop: f64, h: f64, k: usize, steps: usize) -> (f64, f64, f64) {
    let t = start + (k - 1) as f64 * h;
    let t1 = (start + k as f64 * h).min(stop);
    let short = k == steps && (t1 - t) < h * (1.0 - 1e-9);
    (t, t1, if short { t1 - t } else { h })
}

/// One CSV row per communication point: every recorded Real output of a participant read by
/// one `get_real` call, the row formatted into one reused line.
struct Rows {
    /// Per participant: the value references of its recorded Real outputs and their columns.
    reals: Vec<(Vec<u32>, Vec<usize>)>,
    /// `(column, participant, vr, kind)` of the recorded Integer/Boolean outputs.
    discrete: Vec<(usize, usize, u32, Discrete)>,
    /// The cells of the row being written, and its text.
    cells: Vec<Cell>,
    buffer: Vec<f64>,
    line: String,
}

#[derive(Clone, Copy)]
enum Cell {
    Real(f64),
    Discrete(i32),
}

impl Rows {
    fn new(columns: &[Column], participants: usize) -> Self {
        let mut reals = vec![(Vec::new(), Vec::new()); participants];
        let mut discrete = Vec::new();
        for (col, &(_, p, vr, kind)) in columns.iter().enumerate() {
            match kind {
                None => {
                    reals[p].0.push(vr);
                    reals[p].1.push(col);
                }
                Some(kind) => discrete.push((col, p, vr, kind)),
            }
        }
        Rows {
            reals,
            discrete,
            cells: vec![Cell::Real(0.0); columns.len()],
            buffer: Vec::new(),
            line: String::new(),
        }
    }

    fn write(
        &mut self,
        sys: &mut System,
        t: f64,
        csv: &mut crate::output::outdir::NamedFile,
    ) -> Result<(), Box<dyn std::error::Error>> {
        use std::fmt::Write as _;
        for (p, (vrs, cols)) in self.reals.iter().enumerate() {
            if vrs.is_empty() {
                continue;
            }
            self.buffer.resize(vrs.len(), 0.0);
            sys.participants[p].get_real(vrs, &mut self.buffer)?;
            for (&col, &v) in cols.iter().zip(&self.buffer) {
                self.cells[col] = Cell::Real(v);
            }
        }
        for &(col, p, vr, kind) in &self.discrete {
            let mut v = [0];
            sys.participants[p].get_discrete(kind, &[vr], &mut v)?;
            self.cells[col] = Cell::Discrete(v[0]);
        }
        self.line.clear();
        write!(self.line, "{t:e}")?;
        for cell in &self.cells {
            match cell {
                Cell::Real(v) => write!(self.line, ",{v:e}")?,
                Cell::Discrete(v) => write!(self.line, ",{v}")?,
            }
        }
        self.line.push('\n');
        csv.write_all(self.line.as_bytes())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::communication_step;

    #[test]
    fn output_intervals_are_whole_multiples_of_the_step() {
        use super::steps_per_row;
        assert_eq!(steps_per_row(0.002, 0.002), Ok(1));
        assert_eq!(steps_per_row(0.01, 0.002), Ok(5));
        assert_eq!(steps_per_row(0.1, 0.001), Ok(100));
        for bad in [0.003, 0.001, 0.0, -0.01, f64::NAN, f64::INFINITY] {
            let e = steps_per_row(bad, 0.002).unwrap_err();
            assert!(
                e.contains("--output-interval") && e.contains("0.002"),
                "{e}"
            );
        }
    }

    /// Every step of the Tsing Ma run (65 059 steps of 2 ms to 130.118 s) has the nominal size
    /// bit for bit, although `t₁ − t` differs from it in most steps; a run whose end is not a
    /// whole number of steps ends with the short remainder.
    #[test]
    fn steps_have_the_nominal_size_except_a_short_last_one() {
        let (h, stop) = (0.002, 130.118);
        let steps = ((stop - 0.0) / h - 1e-9_f64).ceil() as usize;
        assert_eq!(steps, 65_059);
        let mut jittered = 0;
        for k in 1..=steps {
            let (t, t1, hk) = communication_step(0.0, stop, h, k, steps);
            assert_eq!(hk.to_bits(), h.to_bits(), "step {k}");
            jittered += usize::from((t1 - t).to_bits() != h.to_bits());
        }
        assert!(jittered > steps / 2, "{jittered} of {steps}");
        let stop = 1.0005;
        let steps = (stop / h - 1e-9_f64).ceil() as usize;
        assert_eq!(steps, 501);
        let (t, t1, hk) = communication_step(0.0, stop, h, steps, steps);
        assert_eq!((t, t1), (1.0, stop));
        assert!((hk - 0.0005).abs() < 1e-12, "{hk}");
    }
}
