//! Responses: what a run records, its maxima, safety factors and ride comfort.
//!
//! Both solvers (monolithic and co-simulation) fill the same [`Sample`] at each output time,
//! so their `history.csv` and `summary.json` are produced by one [`Recorder`].
//!
//! * Deck: displacement and acceleration at named probes (shear centre; vertical + down).
//! * Vehicles: car-body lateral and vertical acceleration at the centre of gravity.
//! * Wheelsets: lateral force Q = F_y, vertical force P = F_z (static plus dynamic), roll
//!   moment M_x, and from them ([`crate::vehicle::WheelLoads`]):
//!   - derail factor, wheelset form (the paper's): Q/P; per-wheel form: |Q| / P of the wheel
//!     the lateral force pushes toward;
//!   - offload factor, wheelset form: ΔP/P̄ = (P0 − P)/P0 with P0 the static wheelset load;
//!     per-wheel form: (P0/2 − P_wheel)/(P0/2), the larger of the two wheels.
//!
//!   Maxima in `summary.json` are maxima of absolute values over all wheelsets and times.
//! * Sperling ride index W per vehicle and direction, from the spectrum of the car-body
//!   acceleration: `W = (Σ Wᵢ¹⁰)^0.1`, `Wᵢ = 0.896 (aᵢ³ F(fᵢ)/fᵢ)^0.1`, aᵢ the amplitude of
//!   the component at fᵢ in cm/s², F the frequency weighting of [`sperling_weight`].

use crate::solver::partitioned::ProbeValues;
use crate::vehicle::WheelLoads;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::io::Write;

/// Everything recorded at one output time.
#[derive(Debug, Clone, Default)]
pub struct Sample {
    pub t: f64,
    pub probes: Vec<ProbeValues>,
    /// Car-body (lateral, vertical) acceleration per vehicle, m/s² (None if not modelled).
    pub vehicles: Vec<[Option<f64>; 2]>,
    /// Force of each wheelset on the rail (F_y, M_x, F_z).
    pub forces: Vec<Vector3<f64>>,
    /// The wheelsets whose force can differ between samples, ascending; every other
    /// wheelset's force is the same at every sample (a moving force). None: any can differ.
    pub forces_varying: Option<Vec<usize>>,
}

/// Static description of what is recorded.
#[derive(Debug, Clone)]
pub struct Layout {
    pub probe_names: Vec<String>,
    /// Per vehicle: (has lateral, has vertical) car-body acceleration.
    pub vehicles: Vec<[bool; 2]>,
    /// Per wheelset: static vertical load P0 (N) and contact distance (m).
    pub wheelsets: Vec<(f64, f64)>,
    /// Per train, its number of vehicles and of wheelsets, train after train as `vehicles`
    /// and `wheelsets` hold them (empty: one train). With several, the columns of train
    /// k ≥ 2 are named `train<k>.veh<i>…` and `train<k>.ws<w>…`, numbered within the train.
    pub trains: Vec<[usize; 2]>,
}

impl Layout {
    /// The train of each vehicle (`d = 0`) or wheelset (`d = 1`), and its number within the
    /// train (1-based).
    pub fn numbered(&self, d: usize) -> Vec<(usize, usize)> {
        let n = [self.vehicles.len(), self.wheelsets.len()][d];
        let mut out = Vec::with_capacity(n);
        for (k, t) in self.trains.iter().enumerate() {
            out.extend((1..=t[d]).map(|i| (k, i)));
        }
        let from = out.len();
        out.extend((from..n).map(|i| (0, i + 1)));
        out.truncate(n);
        out
    }

    /// `veh3` or `train2.veh3` (`what` = `veh` or `ws`) of a train's item `i`.
    fn item_name(what: &str, (k, i): (usize, usize)) -> String {
        match k {
            0 => format!("{what}{i}"),
            _ => format!("train{}.{what}{i}", k + 1),
        }
    }

    /// Column names of `history.csv`.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec!["time_s".to_string()];
        for p in &self.probe_names {
            c.push(format!("{p}.vertical_displacement_m"));
            c.push(format!("{p}.vertical_acceleration_m_s2"));
            c.push(format!("{p}.lateral_displacement_m"));
            c.push(format!("{p}.lateral_acceleration_m_s2"));
            c.push(format!("{p}.torsion_rad"));
        }
        for (v, at) in self.vehicles.iter().zip(self.numbered(0)) {
            let name = Self::item_name("veh", at);
            if v[0] {
                c.push(format!("{name}.lateral_acceleration_m_s2"));
            }
            if v[1] {
                c.push(format!("{name}.vertical_acceleration_m_s2"));
            }
        }
        for at in self.numbered(1) {
            let k = Self::item_name("ws", at);
            c.push(format!("{k}.lateral_force_n"));
            c.push(format!("{k}.vertical_force_n"));
            c.push(format!("{k}.roll_moment_nm"));
            c.push(format!("{k}.derail_factor"));
            c.push(format!("{k}.offload_factor"));
        }
        c
    }
}

/// Maxima of one probe.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ProbeMax {
    pub x_m: f64,
    pub vertical_displacement_max_m: f64,
    pub vertical_acceleration_max_m_s2: f64,
    pub lateral_displacement_max_m: f64,
    pub lateral_acceleration_max_m_s2: f64,
    /// Largest |torsion| of the deck, rad.
    #[serde(default)]
    pub torsion_max_rad: f64,
}

/// Vehicle maxima over all vehicles.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct VehicleMax {
    pub vertical_acceleration_max_m_s2: f64,
    pub lateral_acceleration_max_m_s2: f64,
    /// Sperling index per vehicle, vertical (None if not modelled).
    pub sperling_vertical: Vec<Option<f64>>,
    /// Sperling index per vehicle, lateral.
    pub sperling_lateral: Vec<Option<f64>>,
}

/// Safety maxima (absolute values) over all wheelsets and times.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SafetyMax {
    /// Wheelset form Q/P.
    pub derail_factor_max: f64,
    /// Wheelset form (P0 − P)/P0.
    pub offload_factor_max: f64,
    /// Per-wheel form of the derail factor.
    pub derail_factor_wheel_max: f64,
    /// Per-wheel form of the offload factor.
    pub offload_factor_wheel_max: f64,
    /// Largest lateral wheelset force |Q|, N.
    pub lateral_force_max_n: f64,
}

impl SafetyMax {
    /// Takes one wheelset's loads into the maxima (of the absolute values).
    pub fn include(&mut self, l: &WheelLoads) {
        self.derail_factor_max = self.derail_factor_max.max(l.derail.abs());
        self.offload_factor_max = self.offload_factor_max.max(l.offload.abs());
        self.derail_factor_wheel_max = self.derail_factor_wheel_max.max(l.derail_wheel.abs());
        self.offload_factor_wheel_max = self.offload_factor_wheel_max.max(l.offload_wheel.abs());
        self.lateral_force_max_n = self.lateral_force_max_n.max(l.q.abs());
    }
}

/// The maxima of one train of several.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainMax {
    /// Largest car-body vertical acceleration, m/s².
    pub vertical_acceleration_max_m_s2: f64,
    /// Largest car-body lateral acceleration, m/s².
    pub lateral_acceleration_max_m_s2: f64,
    pub safety: SafetyMax,
}

/// Accumulates samples: writes history rows and tracks maxima.
pub struct Recorder<W: Write> {
    pub layout: Layout,
    pub probes: Vec<ProbeMax>,
    pub vehicles: VehicleMax,
    pub safety: SafetyMax,
    /// Per train of several ([`Layout::trains`]), its maxima (empty with one train).
    pub by_train: Vec<TrainMax>,
    /// The train of each vehicle and of each wheelset.
    train_of: [Vec<usize>; 2],
    acc_history: Vec<[Vec<f64>; 2]>,
    times: Vec<f64>,
    out: Option<W>,
    pub rows: usize,
    /// The row being written and its text (kept to reuse their allocations).
    row: Vec<f64>,
    line: String,
    /// Per wheelset, the force of the last sample (its bits) and the loads derived from it:
    /// a force that has not changed (a moving force) has the same loads and maxima.
    last_loads: Vec<Option<([u64; 3], WheelLoads)>>,
}

impl<W: Write> Recorder<W> {
    /// `probe_x` gives the probe positions (for the summary); `out` receives `history.csv`.
    pub fn new(layout: Layout, probe_x: &[f64], mut out: Option<W>) -> std::io::Result<Self> {
        if let Some(o) = out.as_mut() {
            writeln!(o, "{}", layout.columns().join(","))?;
        }
        let several = layout.trains.len() > 1;
        let train_of = [0, 1].map(|d| match several {
            true => layout.numbered(d).iter().map(|a| a.0).collect(),
            false => Vec::new(),
        });
        Ok(Recorder {
            by_train: match several {
                true => vec![TrainMax::default(); layout.trains.len()],
                false => Vec::new(),
            },
            train_of,
            probes: probe_x
                .iter()
                .map(|&x| ProbeMax {
                    x_m: x,
                    ..Default::default()
                })
                .collect(),
            vehicles: VehicleMax::default(),
            safety: SafetyMax::default(),
            acc_history: vec![[Vec::new(), Vec::new()]; layout.vehicles.len()],
            times: Vec::new(),
            layout,
            out,
            rows: 0,
            row: Vec::new(),
            line: String::new(),
            last_loads: Vec::new(),
        })
    }

    /// Record one sample (also writes a history row when `write_row`).
    pub fn record(&mut self, s: &Sample, write_row: bool) -> std::io::Result<()> {
        // the row is assembled only when it is written (the maxima take every sample)
        let write_row = write_row && self.out.is_some();
        let mut row = std::mem::take(&mut self.row);
        row.clear();
        if write_row {
            row.push(s.t);
        }
        for (p, m) in s.probes.iter().zip(self.probes.iter_mut()) {
            m.vertical_displacement_max_m = m.vertical_displacement_max_m.max(p.z.abs());
            m.vertical_acceleration_max_m_s2 = m.vertical_acceleration_max_m_s2.max(p.z_dd.abs());
            m.lateral_displacement_max_m = m.lateral_displacement_max_m.max(p.y.abs());
            m.lateral_acceleration_max_m_s2 = m.lateral_acceleration_max_m_s2.max(p.y_dd.abs());
            m.torsion_max_rad = m.torsion_max_rad.max(p.theta.abs());
            if write_row {
                row.extend([p.z, p.z_dd, p.y, p.y_dd, p.theta]);
            }
        }
        self.times.push(s.t);
        for (i, v) in s.vehicles.iter().enumerate() {
            if let Some(&k) = self.train_of[0].get(i) {
                let t = &mut self.by_train[k];
                let [lat, ver] = v.map(|a| a.map_or(0.0, f64::abs));
                t.lateral_acceleration_max_m_s2 = t.lateral_acceleration_max_m_s2.max(lat);
                t.vertical_acceleration_max_m_s2 = t.vertical_acceleration_max_m_s2.max(ver);
            }
            if let Some(a) = v[0] {
                self.vehicles.lateral_acceleration_max_m_s2 =
                    self.vehicles.lateral_acceleration_max_m_s2.max(a.abs());
                self.acc_history[i][0].push(a);
                if write_row {
                    row.push(a);
                }
            }
            if let Some(a) = v[1] {
                self.vehicles.vertical_acceleration_max_m_s2 =
                    self.vehicles.vertical_acceleration_max_m_s2.max(a.abs());
                self.acc_history[i][1].push(a);
                if write_row {
                    row.push(a);
                }
            }
        }
        // Without a row, once every wheelset's loads are known, only the forces that can vary
        // need a look (the others would find their memo), four at a time (their memo left as
        // it was: a force equal to its memo's bit for bit still has its loads).
        if !write_row && self.last_loads.len() == s.forces.len() {
            match &s.forces_varying {
                Some(varying) => self.include_loads(varying.iter().copied(), &s.forces),
                None => self.include_loads(0..s.forces.len(), &s.forces),
            }
        } else {
            self.last_loads.resize(s.forces.len(), None);
            for (w, f) in s.forces.iter().enumerate() {
                let l = self.loads(w, f);
                if write_row {
                    row.extend([f.x, f.z, f.y, l.derail, l.offload]);
                }
            }
        }
        let written = match self.out.as_mut() {
            Some(o) if write_row => {
                let line = &mut self.line;
                line.clear();
                for (k, v) in row.iter().enumerate() {
                    if k > 0 {
                        line.push(',');
                    }
                    let _ = std::fmt::Write::write_fmt(line, format_args!("{v:e}"));
                }
                line.push('\n');
                let written = o.write_all(line.as_bytes());
                self.rows += usize::from(written.is_ok());
                written
            }
            _ => Ok(()),
        };
        self.row = row;
        written
    }

    /// The loads of `wheelsets` under their `forces` taken into the safety maxima, four at a
    /// time ([`WheelLoads::from_forces4`]; the lanes of a last group of fewer repeat its last
    /// wheelset, which changes no maximum).
    fn include_loads(
        &mut self,
        mut wheelsets: impl Iterator<Item = usize>,
        forces: &[Vector3<f64>],
    ) {
        while let Some(first) = wheelsets.next() {
            let mut four = [first; 4];
            for lane in &mut four[1..] {
                *lane = wheelsets.next().unwrap_or(first);
            }
            let (mut q, mut m, mut p, mut p0, mut b) =
                ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
            for (j, &w) in four.iter().enumerate() {
                let f = &forces[w];
                (q[j], m[j], p[j]) = (f.x, f.y, f.z);
                (p0[j], b[j]) = self.layout.wheelsets[w];
            }
            for (l, &w) in WheelLoads::from_forces4(q, m, p, p0, b).iter().zip(&four) {
                self.safety.include(l);
                if let Some(&k) = self.train_of[1].get(w) {
                    self.by_train[k].safety.include(l);
                }
            }
        }
    }

    /// The loads of wheelset `w` under force `f`, taken into the safety maxima, derived again
    /// only when `f` differs bit for bit from the wheelset's force of the last sample.
    fn loads(&mut self, w: usize, f: &Vector3<f64>) -> WheelLoads {
        let bits = [f.x.to_bits(), f.y.to_bits(), f.z.to_bits()];
        match &self.last_loads[w] {
            Some((was, l)) if *was == bits => *l,
            _ => {
                let (p0, b) = self.layout.wheelsets[w];
                let l = WheelLoads::from_force(f, p0, b);
                self.safety.include(&l);
                if let Some(&k) = self.train_of[1].get(w) {
                    self.by_train[k].safety.include(&l);
                }
                self.last_loads[w] = Some((bits, l));
                l
            }
        }
    }

    /// Finish: compute Sperling indices, flush the history.
    pub fn finish(&mut self) -> std::io::Result<()> {
        let dt = if self.times.len() > 1 {
            (self.times[self.times.len() - 1] - self.times[0]) / (self.times.len() - 1) as f64
        } else {
            0.0
        };
        let mut records = Vec::new();
        for (i, has) in self.layout.vehicles.iter().enumerate() {
            for (d, dir) in [Direction::Lateral, Direction::Vertical]
                .into_iter()
                .enumerate()
            {
                if has[d] {
                    records.push((self.acc_history[i][d].as_slice(), dir));
                }
            }
        }
        let mut w = sperling_many(&records, dt).into_iter();
        self.vehicles.sperling_lateral.clear();
        self.vehicles.sperling_vertical.clear();
        for has in &self.layout.vehicles {
            let lat = has[0].then(|| w.next().expect("one index per record"));
            let ver = has[1].then(|| w.next().expect("one index per record"));
            self.vehicles.sperling_lateral.push(lat);
            self.vehicles.sperling_vertical.push(ver);
        }
        if let Some(o) = self.out.as_mut() {
            o.flush()?;
        }
        Ok(())
    }

    /// Car-body acceleration histories (lateral, vertical) per vehicle.
    pub fn acceleration_history(&self, vehicle: usize) -> &[Vec<f64>; 2] {
        &self.acc_history[vehicle]
    }
}

/// Direction for the Sperling weighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Vertical,
    Lateral,
}

/// Sperling frequency weighting F(f): vertical 0.325 f² (0.5–5.9 Hz), 400/f² (5.9–20 Hz), 1
/// above; lateral 0.8 f² (0.5–5.4 Hz), 650/f² (5.4–26 Hz), 1 above; below 0.5 Hz the
/// low-frequency branch continues.
pub fn sperling_weight(f: f64, dir: Direction) -> f64 {
    match dir {
        Direction::Vertical => {
            if f <= 5.9 {
                0.325 * f * f
            } else if f <= 20.0 {
                400.0 / (f * f)
            } else {
                1.0
            }
        }
        Direction::Lateral => {
            if f <= 5.4 {
                0.8 * f * f
            } else if f <= 26.0 {
                650.0 / (f * f)
            } else {
                1.0
            }
        }
    }
}

/// Sperling index of an acceleration record (m/s², uniform step `dt`): amplitude spectrum by
/// FFT, components from 0.5 to 30 Hz.
pub fn sperling(acc: &[f64], dt: f64, dir: Direction) -> f64 {
    sperling_many(&[(acc, dir)], dt)[0]
}

/// [`sperling`] of several records of one sampling interval `dt`, each bit for bit the same:
/// one FFT plan per record length, shared, and the records spread over the available cores.
pub fn sperling_many(records: &[(&[f64], Direction)], dt: f64) -> Vec<f64> {
    let mut planner = rustfft::FftPlanner::new();
    let plans: Vec<_> = records
        .iter()
        .map(|(acc, _)| (acc.len() >= 4 && dt > 0.0).then(|| planner.plan_fft_forward(acc.len())))
        .collect();
    let mut out = vec![0.0; records.len()];
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let per = records.len().div_ceil(threads).max(1);
    type Plan = std::sync::Arc<dyn rustfft::Fft<f64>>;
    let run = |records: &[(&[f64], Direction)], plans: &[Option<Plan>], out: &mut [f64]| {
        let mut buf = Vec::new();
        for (((acc, dir), plan), w) in records.iter().zip(plans).zip(out) {
            if let Some(plan) = plan {
                *w = sperling_with(plan.as_ref(), acc, dt, *dir, &mut buf);
            }
        }
    };
    let mut chunks = records
        .chunks(per)
        .zip(plans.chunks(per))
        .zip(out.chunks_mut(per));
    // the first chunk on this thread, the others on threads of their own
    let first = chunks.next();
    std::thread::scope(|scope| {
        for ((records, plans), out) in chunks {
            scope.spawn(move || run(records, plans, out));
        }
        if let Some(((records, plans), out)) = first {
            run(records, plans, out);
        }
    });
    out
}

/// The index of one record (at least 4 values, `dt > 0`) by `fft`, the forward FFT of its
/// length, in the buffer `buf`.
fn sperling_with(
    fft: &dyn rustfft::Fft<f64>,
    acc: &[f64],
    dt: f64,
    dir: Direction,
    buf: &mut Vec<rustfft::num_complex::Complex<f64>>,
) -> f64 {
    let n = acc.len();
    buf.clear();
    buf.extend(
        acc.iter()
            .map(|&a| rustfft::num_complex::Complex::new(a * 100.0, 0.0)),
    );
    fft.process(buf);
    let df = 1.0 / (n as f64 * dt);
    let mut sum = 0.0;
    for (k, c) in buf.iter().enumerate().take(n / 2 + 1).skip(1) {
        let f = k as f64 * df;
        if !(0.5..=30.0).contains(&f) {
            continue;
        }
        let amp = 2.0 * c.norm() / n as f64; // cm/s²
        let wi = 0.896 * (amp.powi(3) * sperling_weight(f, dir) / f).powf(0.1);
        sum += wi.powi(10);
    }
    sum.powf(0.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pure sine of amplitude a (m/s²) at f (Hz), sampled over whole periods, has one
    /// spectral line: W = 0.896 (a_cm³ F(f) / f)^0.1 exactly.
    #[test]
    fn sperling_of_a_pure_sine_is_the_closed_form() {
        for (f, a, dir) in [
            (1.0, 0.3, Direction::Vertical),
            (8.0, 0.5, Direction::Vertical),
            (2.5, 0.2, Direction::Lateral),
        ] {
            let dt = 0.005;
            let n = (20.0 / dt) as usize; // 20 s: an integer number of periods
            let acc: Vec<f64> = (0..n)
                .map(|k| a * (2.0 * std::f64::consts::PI * f * k as f64 * dt).sin())
                .collect();
            let w = sperling(&acc, dt, dir);
            let expected = 0.896 * ((100.0 * a).powi(3) * sperling_weight(f, dir) / f).powf(0.1);
            assert!(
                (w - expected).abs() < 1e-9 * expected,
                "f = {f}: {w} vs {expected}"
            );
        }
    }

    /// A wheelset whose force repeats, then changes, then repeats: the safety maxima and the
    /// history rows are those of each sample's loads taken one by one.
    #[test]
    fn repeated_forces_give_the_maxima_and_rows_of_every_sample() {
        let layout = Layout {
            probe_names: Vec::new(),
            vehicles: Vec::new(),
            wheelsets: vec![(1e5, 1.5), (1e5, 1.5)],
            trains: Vec::new(),
        };
        let forces = [
            [Vector3::new(1e3, 0.0, 1e5), Vector3::new(0.0, 0.0, 1e5)],
            [Vector3::new(1e3, 0.0, 1e5), Vector3::new(0.0, 0.0, 1e5)],
            [Vector3::new(-4e3, 2e3, 0.8e5), Vector3::new(0.0, 0.0, 1e5)],
            [
                Vector3::new(-4e3, 2e3, 0.8e5),
                Vector3::new(5e2, -1e3, 1.1e5),
            ],
            [Vector3::new(1e3, 0.0, 1e5), Vector3::new(5e2, -1e3, 1.1e5)],
        ];
        let mut rec = Recorder::new(layout.clone(), &[], Some(Vec::new())).unwrap();
        let mut expected = SafetyMax::default();
        let mut rows = String::new();
        for (k, f) in forces.iter().enumerate() {
            let sample = Sample {
                t: k as f64,
                probes: Vec::new(),
                vehicles: Vec::new(),
                forces: f.to_vec(),
                forces_varying: None,
            };
            rec.record(&sample, true).unwrap();
            rows.push_str(&format!("{:e}", k as f64));
            for (f, &(p0, b)) in f.iter().zip(&layout.wheelsets) {
                let l = WheelLoads::from_force(f, p0, b);
                expected.include(&l);
                for v in [f.x, f.z, f.y, l.derail, l.offload] {
                    rows.push_str(&format!(",{v:e}"));
                }
            }
            rows.push('\n');
        }
        let s = &rec.safety;
        assert_eq!(s.derail_factor_max, expected.derail_factor_max);
        assert_eq!(s.offload_factor_max, expected.offload_factor_max);
        assert_eq!(s.derail_factor_wheel_max, expected.derail_factor_wheel_max);
        assert_eq!(
            s.offload_factor_wheel_max,
            expected.offload_factor_wheel_max
        );
        assert_eq!(s.lateral_force_max_n, expected.lateral_force_max_n);
        assert!(expected.offload_factor_max > 0.1 && expected.derail_factor_max > 0.01);
        let text = String::from_utf8(rec.out.take().unwrap()).unwrap();
        let body: String = text.lines().skip(1).map(|l| format!("{l}\n")).collect();
        assert_eq!(body, rows);
    }

    /// Several records at once (of two lengths, more records than cores, one too short)
    /// give each record's index bit for bit.
    #[test]
    fn sperling_of_many_records_is_each_records_index() {
        let dt = 0.002;
        let record = |n: usize, f: f64, phase: f64| -> Vec<f64> {
            (0..n)
                .map(|k| 0.4 * (2.0 * std::f64::consts::PI * f * k as f64 * dt + phase).sin())
                .collect()
        };
        let data: Vec<(Vec<f64>, Direction)> = (0..9)
            .map(|i| {
                let n = if i % 3 == 0 { 3253 * 4 } else { 6000 };
                let dir = if i % 2 == 0 {
                    Direction::Lateral
                } else {
                    Direction::Vertical
                };
                (record(n, 1.0 + i as f64, 0.3 * i as f64), dir)
            })
            .chain([(vec![1.0, 2.0, 3.0], Direction::Vertical)])
            .collect();
        let records: Vec<(&[f64], Direction)> =
            data.iter().map(|(a, d)| (a.as_slice(), *d)).collect();
        let many = sperling_many(&records, dt);
        assert_eq!(many.len(), records.len());
        for ((acc, dir), w) in records.iter().zip(&many) {
            let mut planner = rustfft::FftPlanner::new();
            let one = if acc.len() < 4 {
                0.0
            } else {
                let plan = planner.plan_fft_forward(acc.len());
                sperling_with(plan.as_ref(), acc, dt, *dir, &mut Vec::new())
            };
            assert_eq!(w.to_bits(), one.to_bits());
        }
        assert!(many[..9].iter().all(|&w| w > 0.0));
        assert_eq!(many[9], 0.0);
    }

    #[test]
    fn sperling_weights_are_continuous_at_their_breaks() {
        assert!((sperling_weight(5.9, Direction::Vertical) - 0.325 * 5.9 * 5.9).abs() < 1e-12);
        assert!((0.325f64 * 5.9 * 5.9 - 400.0 / (5.9 * 5.9)).abs() < 0.05 * 11.3);
        assert!((0.8f64 * 5.4 * 5.4 - 650.0 / (5.4 * 5.4)).abs() < 0.05 * 23.3);
        assert_eq!(sperling_weight(30.0, Direction::Lateral), 1.0);
    }
}
