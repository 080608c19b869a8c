//! SVG plots of a run, drawn from its `history.csv` (the paper's Figures 8–11 for the Tsing Ma
//! case): deck vertical displacement and acceleration at the probes, deck lateral
//! displacement and acceleration, and the car-body accelerations of the first vehicle.

use crate::model::Model;
use plotters::prelude::*;
use std::path::Path;

/// Columns of a history file.
pub struct History {
    pub names: Vec<String>,
    pub columns: Vec<Vec<f64>>,
}

impl History {
    pub fn read(path: &Path) -> Result<History, String> {
        let mut rdr =
            csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let names: Vec<String> = rdr
            .headers()
            .map_err(|e| format!("{}: {e}", path.display()))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut columns = vec![Vec::new(); names.len()];
        for (i, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(|e| format!("{}: {e}", path.display()))?;
            for (c, v) in rec.iter().enumerate() {
                let x: f64 = v.parse().map_err(|_| {
                    format!(
                        "{}:{}: column {} value `{v}` is not a number",
                        path.display(),
                        i + 2,
                        names[c]
                    )
                })?;
                columns[c].push(x);
            }
        }
        Ok(History { names, columns })
    }

    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.columns[i].as_slice())
    }
}

/// Line colours of every plot (plots and `report.html`).
pub(crate) const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// One panel: several series against time.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    ylabel: &str,
    t: &[f64],
    series: &[(String, Vec<f64>)],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (_, s) in series {
        for v in s {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
    }
    if !lo.is_finite() || !hi.is_finite() {
        lo = -1.0;
        hi = 1.0;
    }
    if hi - lo < 1e-300 {
        lo -= 1e-12_f64.max(lo.abs() * 0.1);
        hi += 1e-12_f64.max(hi.abs() * 0.1);
    }
    let pad = 0.05 * (hi - lo);
    let t0 = t.first().copied().unwrap_or(0.0);
    let t1 = t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(ylabel)
        .y_label_formatter(&|v| plain(*v, hi - lo))
        .draw()
        .map_err(|e| e.to_string())?;
    for (k, (name, s)) in series.iter().enumerate() {
        let color = COLORS[k % COLORS.len()];
        chart
            .draw_series(LineSeries::new(
                t.iter().copied().zip(s.iter().copied()),
                color.stroke_width(1),
            ))
            .map_err(|e| e.to_string())?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
    }
    if series.len() > 1 {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// A tick label in plain notation with as many decimals as the axis range needs (two
/// significant digits of it), e.g. `0.25` or `-12`, never `2.500e-1`.
pub(crate) fn plain(v: f64, range: f64) -> String {
    if v.abs() < 1e-12 * range.abs().max(f64::MIN_POSITIVE) {
        return "0".to_string();
    }
    let decimals = if range > 0.0 && range.is_finite() {
        (1.0 - range.log10().floor()).clamp(0.0, 12.0) as usize
    } else {
        3
    };
    format!("{v:.decimals$}")
}

/// A panel: title, y-axis label and named series.
pub(crate) type Panel<'a> = (&'a str, &'a str, Vec<(String, Vec<f64>)>);

/// A figure of panels stacked vertically, against the time `t`.
pub(crate) fn figure(path: &Path, panels: &[Panel<'_>], t: &[f64]) -> Result<(), String> {
    let height = 320 * panels.len() as u32;
    let root = SVGBackend::new(path, (1000, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len(), 1));
    for (area, (title, ylabel, series)) in areas.iter().zip(panels) {
        panel(area, title, ylabel, t, series)?;
    }
    root.present()
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Write the run's plots next to its history; `case` (e.g. "tsing-ma, 70 km/h") goes into
/// every title. The lateral deck figure only where the deck moves sideways. The units are
/// those of the short summary: displacements in mm, accelerations in m/s².
pub fn write_run_plots(
    out: &Path,
    model: &Model,
    history: &Path,
    case: &str,
) -> Result<(), String> {
    let h = History::read(history)?;
    let t = h.column("time_s").ok_or("history without time_s")?.to_vec();
    let probe_series = |suffix: &str, scale: f64| -> Vec<(String, Vec<f64>)> {
        model
            .probes
            .iter()
            .filter_map(|(name, _)| {
                h.column(&format!("{name}.{suffix}"))
                    .map(|c| (name.clone(), c.iter().map(|v| v * scale).collect()))
            })
            .collect()
    };
    let titled = |what: &str| format!("{what} — {case}");
    let (vd, va, ld, la) = (
        titled("Deck vertical displacement (+ down)"),
        titled("Deck vertical acceleration"),
        titled("Deck lateral displacement"),
        titled("Deck lateral acceleration"),
    );
    if !model.probes.is_empty() {
        figure(
            &out.join("deck_vertical.svg"),
            &[
                (
                    vd.as_str(),
                    "mm",
                    probe_series("vertical_displacement_m", 1000.0),
                ),
                (
                    va.as_str(),
                    "m/s²",
                    probe_series("vertical_acceleration_m_s2", 1.0),
                ),
            ],
            &t,
        )?;
        // A deck that does not move sideways (a bridge without lateral or torsional modes,
        // such as a vertical beam model) gets no lateral figure, and none left from an
        // earlier run into the same folder.
        let lateral = [
            probe_series("lateral_displacement_m", 1000.0),
            probe_series("lateral_acceleration_m_s2", 1.0),
            probe_series("torsion_rad", 1000.0),
        ];
        let path = out.join("deck_lateral.svg");
        if lateral
            .iter()
            .flatten()
            .any(|(_, v)| v.iter().any(|&x| x != 0.0))
        {
            let [d, a, r] = lateral;
            let lt = titled("Deck torsion");
            figure(
                &path,
                &[
                    (ld.as_str(), "mm", d),
                    (la.as_str(), "m/s²", a),
                    (lt.as_str(), "mrad", r),
                ],
                &t,
            )?;
        } else {
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(format!("{}: {e}", path.display()))
                }
                _ => {}
            }
        }
    }
    // the first car body of each train: `vehicle1_acceleration.svg`, then
    // `train2_vehicle1_acceleration.svg`, …
    for k in 1..=model.trains.len() {
        let (column, file, body) = match k {
            1 => (
                "veh1".to_string(),
                "vehicle1_acceleration.svg".to_string(),
                "Car body 1".to_string(),
            ),
            _ => (
                format!("train{k}.veh1"),
                format!("train{k}_vehicle1_acceleration.svg"),
                format!("Train {k}, car body 1"),
            ),
        };
        let (cl, cv) = (
            titled(&format!("{body} lateral acceleration")),
            titled(&format!("{body} vertical acceleration")),
        );
        let mut veh = Vec::new();
        if let Some(c) = h.column(&format!("{column}.lateral_acceleration_m_s2")) {
            veh.push((
                cl.as_str(),
                "m/s²",
                vec![("lateral".to_string(), c.to_vec())],
            ));
        }
        if let Some(c) = h.column(&format!("{column}.vertical_acceleration_m_s2")) {
            veh.push((
                cv.as_str(),
                "m/s²",
                vec![("vertical".to_string(), c.to_vec())],
            ));
        }
        if !veh.is_empty() {
            figure(&out.join(file), &veh, &t)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::plain;

    #[test]
    fn tick_labels_are_plain_numbers() {
        assert_eq!(plain(0.5, 1.0), "0.5");
        assert_eq!(plain(0.25, 0.5), "0.25");
        assert_eq!(plain(-12.0, 40.0), "-12");
        assert_eq!(plain(0.0012, 0.004), "0.0012");
        assert_eq!(plain(1e-20, 1.0), "0");
        assert!(!plain(3.5e-4, 1e-3).contains('e'));
    }
}
