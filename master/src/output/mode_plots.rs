//! The deck components of the first modes drawn as SVG.

use plotters::prelude::*;
use std::path::Path;
use tbi_dynamics::bridge::ModeSet;

/// Lever arm that turns torsion into a comparable edge displacement in the plots, m.
const TORSION_ARM_M: f64 = 18.0;

/// Plot the deck components of the first `n` modes: lateral and vertical displacement and
/// torsion times an 18 m arm, all scaled by one factor per mode (largest component = 1).
pub fn plot_shapes(path: &Path, set: &ModeSet, n: usize) -> Result<(), String> {
    let n = n.min(set.modes.len());
    let root = SVGBackend::new(path, (1000, 220 * n as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let x0 = set.x_m[0];
    let x1 = *set.x_m.last().unwrap_or(&1.0);
    for (area, m) in root.split_evenly((n, 1)).iter().zip(&set.modes) {
        let peak = |v: &[f64]| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let scale = peak(&m.lateral)
            .max(peak(&m.vertical))
            .max(TORSION_ARM_M * peak(&m.torsion));
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("{} — {:.4} Hz", m.label, m.frequency_hz),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(25)
            .y_label_area_size(40)
            .build_cartesian_2d(x0..x1, -1.1f64..1.1f64)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .draw()
            .map_err(|e| e.to_string())?;
        if scale == 0.0 {
            continue;
        }
        for (vals, factor, name, color) in [
            (&m.vertical, 1.0, "vertical", RGBColor(31, 119, 180)),
            (&m.lateral, 1.0, "lateral", RGBColor(214, 39, 40)),
            (
                &m.torsion,
                TORSION_ARM_M,
                "torsion × 18 m",
                RGBColor(44, 160, 44),
            ),
        ] {
            chart
                .draw_series(LineSeries::new(
                    set.x_m
                        .iter()
                        .zip(vals.iter())
                        .map(|(x, v)| (*x, factor * v / scale)),
                    color,
                ))
                .map_err(|e| e.to_string())?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    root.present()
        .map_err(|e| format!("{}: {e}", path.display()))
}
