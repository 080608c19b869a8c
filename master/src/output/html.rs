//! The parts of a self-contained HTML report (inline SVG, no scripts, no external
//! resources): line charts with a limit line and labelled markers, tables, the page.
//!
//! The series take the colours of [`PALETTE`], ten qualitative colours none of which is
//! the limit line's red ([`LIMIT_COLOR`]).
use plotters::prelude::*;
use std::fmt::Write as _;

/// One line of a chart: its label and points.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// Ten qualitative colours for series (Tableau 10 with its red replaced by a dark blue).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(57, 59, 121),
];

/// The colour of a limit line.
pub const LIMIT_COLOR: RGBColor = RGBColor(214, 39, 40);

/// What a chart marks besides its series.
#[derive(Default)]
pub struct Marks {
    /// A horizontal line (value, label), e.g. a limit.
    pub limit: Option<(f64, String)>,
    /// Vertical lines at these abscissae.
    pub verticals: Vec<f64>,
    /// Labelled markers (x, series index, label): a triangle in the series' colour along
    /// the top of the chart, one row per series, with its label beside it.
    pub markers: Vec<(f64, usize, String)>,
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
        let height = if marks.markers.is_empty() { 420 } else { 560 };
        let root = SVGBackend::with_string(&mut svg, (900, height)).into_drawing_area();
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
            .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad + marker_room(marks, y1 - y0)))
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
            c.draw_series(DashedLineSeries::new(
                [(x0, *l), (x1, *l)],
                8,
                5,
                ShapeStyle::from(&LIMIT_COLOR).stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(label.clone())
            .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], LIMIT_COLOR));
        }
        let rows = series.len().max(1) as f64;
        let room = marker_room(marks, y1 - y0);
        for (x, k, label) in &marks.markers {
            if *x < x0 || *x > x1 {
                continue;
            }
            let color = PALETTE[k % PALETTE.len()];
            let y = y1 + pad + room * (1.0 - (*k as f64 + 0.5) / rows);
            c.draw_series([EmptyElement::at((*x, y))
                + TriangleMarker::new((0, 0), 5, color.filled())
                + Text::new(
                    label.clone(),
                    (6, -6),
                    ("sans-serif", 10).into_font().color(&color),
                )])
            .map_err(|e| e.to_string())?;
        }
        for (i, s) in series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
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
            .position(if marks.markers.is_empty() {
                SeriesLabelPosition::UpperLeft
            } else {
                SeriesLabelPosition::MiddleLeft
            })
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// The height above the data kept for the marker rows.
fn marker_room(marks: &Marks, span: f64) -> f64 {
    if marks.markers.is_empty() {
        0.0
    } else {
        0.45 * span
    }
}

/// Text safe inside HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// An HTML table of `header` and `rows` (text escaped).
pub fn table(header: &[String], rows: &[Vec<String>]) -> String {
    let mut h = String::from("<table>\n<tr>");
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
    h.push_str("</table>\n");
    h
}

/// A self-contained page: `title` and `body` (HTML).
pub fn page(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{t}</title>\n\
         <style>body{{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}}\
         table{{border-collapse:collapse;margin:0.5em 0}}td,th{{border:1px solid #bbb;padding:3px 8px;text-align:right}}\
         th{{background:#eee}}td:first-child{{text-align:left}}.pass{{color:#1a7f1a;font-weight:bold}}.fail{{color:#c00;font-weight:bold}}\
         figure{{margin:1em 0}}code{{background:#f4f4f4;padding:1px 4px}}</style>\n</head>\n<body>\n<h1>{t}</h1>\n{body}</body>\n</html>\n",
        t = escape(title)
    )
}
