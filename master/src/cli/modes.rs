//! `tbi modes`: the bridge's modes as a table, a modes file and plots of the first shapes.

use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tbi_dynamics::bridge::{Mode, ModeSet, FORMAT_TAG};

/// Command-line arguments of `tbi modes`.
#[derive(Debug, Clone, clap::Args)]
pub struct ModesArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Output folder for modes.csv, modes.md and mode_shapes.svg.
    #[arg(long, default_value = "tbi-out/modes")]
    pub out: PathBuf,
}

/// Measured Tsing Ma frequencies (domain reference §3), Hz, by mode label.
pub const TSING_MA_TARGETS: [(&str, &str, f64); 6] = [
    ("L-S-1", "1st lateral symmetric", 0.069),
    ("V-A-1", "1st vertical antisymmetric", 0.113),
    ("V-S-1", "1st vertical symmetric", 0.139),
    ("L-A-1", "1st lateral antisymmetric", 0.164),
    ("V-S-2", "2nd vertical symmetric", 0.184),
    ("T-S-1", "1st torsional", 0.267),
];

/// The scenario bridge's modes as a [`ModeSet`] (analytic shapes sampled at 401 nodes).
pub fn mode_set(s: &crate::scenario::Scenario) -> Result<ModeSet, String> {
    match crate::model::nodal_modes(s).map_err(|e| e.to_string())? {
        Some((mut set, modal, _)) => {
            set.modes.truncate(modal.modes);
            Ok(set)
        }
        None => {
            let modal = crate::model::build_bridge(s).map_err(|e| e.to_string())?;
            let n = 401;
            let xs: Vec<f64> = (0..n)
                .map(|i| modal.x_start_m + modal.length_m() * i as f64 / (n - 1) as f64)
                .collect();
            let nb = modal.n_modes();
            let mut modes: Vec<Mode> = (0..nb)
                .map(|k| Mode {
                    label: modal.labels[k].clone(),
                    frequency_hz: modal.frequencies_hz[k],
                    damping_ratio: Some(modal.damping[k]),
                    lateral: Vec::with_capacity(n),
                    vertical: Vec::with_capacity(n),
                    torsion: Vec::with_capacity(n),
                })
                .collect();
            let mut sh = vec![[0.0; 3]; nb];
            for &x in &xs {
                modal.deck_shapes(x, &mut sh);
                for (m, v) in modes.iter_mut().zip(&sh) {
                    m.lateral.push(v[0]);
                    m.vertical.push(v[1]);
                    m.torsion.push(v[2]);
                }
            }
            Ok(ModeSet {
                format: FORMAT_TAG.to_string(),
                x_m: xs,
                modes,
            })
        }
    }
}

/// The table of modes (Markdown), with the Tsing Ma targets when they apply.
pub fn table(set: &ModeSet, targets: bool) -> String {
    let mut t = String::from("| mode | frequency (Hz) | type |\n|---:|---:|---|\n");
    for (k, m) in set.modes.iter().enumerate() {
        let _ = writeln!(t, "| {} | {:.4} | {} |", k + 1, m.frequency_hz, m.label);
    }
    if targets {
        t.push_str(
            "\n| target | measured (Hz) | model (Hz) | difference |\n|---|---:|---:|---:|\n",
        );
        for (label, name, f) in TSING_MA_TARGETS {
            match set.modes.iter().find(|m| m.label == label) {
                Some(m) => {
                    let _ = writeln!(
                        t,
                        "| {name} ({label}) | {f:.3} | {:.4} | {:+.1} % |",
                        m.frequency_hz,
                        100.0 * (m.frequency_hz / f - 1.0)
                    );
                }
                None => {
                    let _ = writeln!(t, "| {name} ({label}) | {f:.3} | not among the modes | |");
                }
            }
        }
    }
    t
}

pub fn main(args: ModesArgs) -> Result<(), Box<dyn std::error::Error>> {
    let s = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    let set = mode_set(&s)?;
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let csv = args.out.join("modes.csv");
    set.write(&csv)
        .map_err(|e| format!("{}: {e}", csv.display()))?;
    let t = table(
        &set,
        matches!(s.bridge, crate::scenario::Bridge::Suspension { .. }),
    );
    std::fs::write(args.out.join("modes.md"), &t)?;
    plot_shapes(&args.out.join("mode_shapes.svg"), &set, 6)?;
    crate::say!("{t}");
    eprintln!(
        "tbi: modes.csv, modes.md and mode_shapes.svg in {}",
        args.out.display()
    );
    Ok(())
}

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
