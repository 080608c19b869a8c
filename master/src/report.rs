//! `report.html` of a trains × speeds sweep ([`crate::envelope`]): one self-contained file
//! (inline SVG, no scripts, no external resources) with the checks and their pass/fail lines,
//! the governing cases, the envelopes against speed per train (deck acceleration with the
//! limit line and the resonance speeds of the governing train, deck displacement, φ'dyn),
//! the governing time history, and the table of each train's maxima.

use crate::plots::COLORS;
use plotters::prelude::*;
use std::fmt::Write as _;

/// One line of a chart: its label and points.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// What a chart marks besides its series.
#[derive(Default)]
pub struct Marks {
    /// A horizontal line (value, label), e.g. a limit.
    pub limit: Option<(f64, String)>,
    /// Vertical lines at these abscissae (e.g. resonance speeds).
    pub verticals: Vec<f64>,
}

/// An SVG line chart as text.
pub fn chart(
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[Series],
    marks: &Marks,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let pts = series.iter().flat_map(|s| s.points.iter());
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64, 0.0_f64);
        for &(x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if let Some((l, _)) = &marks.limit {
            y1 = y1.max(*l);
        }
        if !x0.is_finite() || x1 <= x0 {
            x0 = x0.min(0.0);
            x1 = x0 + 1.0;
        }
        if y1 <= y0 {
            y1 = y0 + 1.0;
        }
        let pad = 0.05 * (y1 - y0);
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .draw()
            .map_err(|e| e.to_string())?;
        for &v in &marks.verticals {
            if v >= x0 && v <= x1 {
                c.draw_series(LineSeries::new(
                    [(v, y0 - pad), (v, y1 + pad)],
                    ShapeStyle::from(&BLACK.mix(0.35)).stroke_width(1),
                ))
                .map_err(|e| e.to_string())?;
            }
        }
        if let Some((l, label)) = &marks.limit {
            c.draw_series(LineSeries::new(
                [(x0, *l), (x1, *l)],
                ShapeStyle::from(&RED).stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(label.clone())
            .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], RED));
        }
        for (i, s) in series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            c.draw_series(LineSeries::new(
                s.points.iter().copied(),
                color.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color));
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Text safe inside HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The report's parts, in order.
pub struct Report {
    pub title: String,
    /// Lines describing the case (bridge, damping, modes).
    pub facts: Vec<String>,
    /// (check, passed, detail).
    pub checks: Vec<(String, bool, String)>,
    /// Inline SVG charts with their captions.
    pub charts: Vec<(String, String)>,
    /// A table: header and rows.
    pub table: (Vec<String>, Vec<Vec<String>>),
}

impl Report {
    pub fn html(&self) -> String {
        let mut h = String::new();
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
             <style>body{{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}}\
             table{{border-collapse:collapse}}td,th{{border:1px solid #bbb;padding:3px 8px;text-align:right}}\
             th{{background:#eee}}.pass{{color:#1a7f1a;font-weight:bold}}.fail{{color:#c00;font-weight:bold}}\
             figure{{margin:1em 0}}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            escape(&self.title),
            escape(&self.title)
        );
        h.push_str("<ul>\n");
        for f in &self.facts {
            let _ = writeln!(h, "<li>{}</li>", escape(f));
        }
        h.push_str("</ul>\n<h2>Checks</h2>\n<ul>\n");
        for (name, ok, detail) in &self.checks {
            let (class, word) = if *ok {
                ("pass", "PASS")
            } else {
                ("fail", "FAIL")
            };
            let _ = writeln!(
                h,
                "<li class=\"check\"><span class=\"{class}\">{word}</span> {}: {}</li>",
                escape(name),
                escape(detail)
            );
        }
        h.push_str("</ul>\n");
        for (caption, svg) in &self.charts {
            let _ = writeln!(
                h,
                "<figure>{svg}<figcaption>{}</figcaption></figure>",
                escape(caption)
            );
        }
        let (header, rows) = &self.table;
        h.push_str("<h2>Maxima per train</h2>\n<table>\n<tr>");
        for c in header {
            let _ = write!(h, "<th>{}</th>", escape(c));
        }
        h.push_str("</tr>\n");
        for r in rows {
            h.push_str("<tr>");
            for c in r {
                let _ = write!(h, "<td>{}</td>", escape(c));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</table>\n</body>\n</html>\n");
        h
    }
}
