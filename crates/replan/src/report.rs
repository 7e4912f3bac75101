//! Summaries of replanning runs: medians and percentiles, and an SVG scatter chart of an
//! incremental planner's expansions per replan against A* from scratch at the same replan.

use std::fmt::Write as _;

use planner_text::xml_escape;

/// The `q`-quantile (0..=1) of `values` by the nearest-rank method on a sorted copy
/// (`None` when empty).
///
/// ```
/// use planner_replan::report::quantile;
/// assert_eq!(quantile(&[5.0, 1.0, 3.0], 0.5), Some(3.0));
/// assert_eq!(quantile(&[1.0, 2.0, 3.0, 4.0], 0.5), Some(2.0));
/// assert_eq!(quantile(&[1.0, 2.0, 3.0, 4.0], 1.0), Some(4.0));
/// assert_eq!(quantile(&[], 0.5), None);
/// ```
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = (q.clamp(0.0, 1.0) * sorted.len() as f64).ceil() as usize;
    Some(sorted[rank.clamp(1, sorted.len()) - 1])
}

/// A log-log scatter chart as SVG: one dot per `(x, y)` pair (values below 1 are drawn
/// at 1), the diagonal `y = x` and the line `y = x / 5` (the 20 % goal) for reference.
///
/// ```
/// use planner_replan::report::scatter_svg;
/// let svg = scatter_svg(&[(100, 5), (1000, 20)], "A* <from scratch>", "D* Lite", "replans");
/// assert!(svg.starts_with("<svg") && svg.contains("A* &lt;from scratch&gt;"));
/// assert_eq!(svg.matches("<circle").count(), 2);
/// ```
pub fn scatter_svg(points: &[(u64, u64)], x_label: &str, y_label: &str, title: &str) -> String {
    let (w, h, left, bottom, top, right) = (640.0, 520.0, 70.0, 60.0, 40.0, 20.0);
    let max = points
        .iter()
        .map(|&(x, y)| x.max(y).max(1))
        .max()
        .unwrap_or(10)
        .max(10) as f64;
    let decades = max.log10().ceil().max(1.0);
    let span_x = w - left - right;
    let span_y = h - top - bottom;
    let px = |v: f64| left + v.max(1.0).log10() / decades * span_x;
    let py = |v: f64| h - bottom - v.max(1.0).log10() / decades * span_y;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(svg, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="20" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        xml_escape(title)
    );
    for d in 0..=decades as u32 {
        let v = 10f64.powi(d as i32);
        let (x, y) = (px(v), py(v));
        let _ = writeln!(
            svg,
            r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">1e{d}</text>"##,
            h - bottom,
            h - bottom + 16.0
        );
        let _ = writeln!(
            svg,
            r##"<line x1="{left}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">1e{d}</text>"##,
            w - right,
            left - 6.0,
            y + 4.0
        );
    }
    let top_value = 10f64.powf(decades);
    let _ = writeln!(
        svg,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="4 3"/>"##,
        px(1.0),
        py(1.0),
        px(top_value),
        py(top_value)
    );
    let _ = writeln!(
        svg,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#c33" stroke-dasharray="2 3"/>"##,
        px(5.0),
        py(1.0),
        px(top_value),
        py(top_value / 5.0)
    );
    for &(x, y) in points {
        let _ = writeln!(
            svg,
            r##"<circle cx="{:.1}" cy="{:.1}" r="1.5" fill="#2a6fdb" fill-opacity="0.35"/>"##,
            px(x as f64),
            py(y as f64)
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + span_x / 2.0,
        h - 18.0,
        xml_escape(x_label)
    );
    let _ = writeln!(
        svg,
        r#"<text x="16" y="{:.1}" text-anchor="middle" transform="rotate(-90 16 {:.1})">{}</text>"#,
        top + span_y / 2.0,
        top + span_y / 2.0,
        xml_escape(y_label)
    );
    svg.push_str("</svg>\n");
    svg
}
