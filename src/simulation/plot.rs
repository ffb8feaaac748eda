//! SVG figures with plotters: for each chosen state, the true state and its estimate (top) and
//! the estimation error (bottom), with labelled axes and legends.

use super::run::Trace;
use super::SimulationError;
use plotters::prelude::*;

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.08).max(1e-9 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

type Series = (Vec<(f64, f64)>, RGBColor, u32, String);

/// At most about `2 × buckets` points: in each bucket of consecutive samples the smallest and
/// the largest value are kept, in time order, so peaks survive (an 800-pixel-wide figure cannot
/// show more, and ten thousand points per line made one page of the book 1.8 MB).
fn thin(points: Vec<(f64, f64)>, buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * buckets {
        return points;
    }
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 1);
    for chunk in points.chunks(size) {
        let lo = chunk
            .iter()
            .copied()
            .fold(chunk[0], |a, b| if b.1 < a.1 { b } else { a });
        let hi = chunk
            .iter()
            .copied()
            .fold(chunk[0], |a, b| if b.1 > a.1 { b } else { a });
        if lo.0 <= hi.0 {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
    if let (Some(last), Some(end)) = (out.last().copied(), points.last().copied()) {
        if last.0 < end.0 {
            out.push(end);
        }
    }
    out
}

/// Tick labels readable at any scale: plain with up to three decimals for ordinary ranges,
/// scientific for tiny or huge ones (a range of 10⁻⁴ labelled "0.0" at every tick said nothing).
fn tick(span: f64) -> impl Fn(&f64) -> String {
    move |v: &f64| {
        if !(1e-2..1e5).contains(&span) {
            format!("{v:.2e}")
        } else {
            let s = format!("{v:.3}");
            let s = s.trim_end_matches('0').trim_end_matches('.');
            if s == "-0" {
                "0".to_string()
            } else {
                s.to_string()
            }
        }
    }
}

/// One panel: labelled axes, the series, a legend.
fn panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    t: (f64, f64),
    y_desc: &str,
    time_unit: &str,
    series: Vec<Series>,
) -> Result<(), SimulationError> {
    let err = |e: &dyn std::fmt::Display| SimulationError::Plot(e.to_string());
    let (lo, hi) = range(series.iter().flat_map(|s| s.0.iter().map(|p| p.1)));
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(t.0..t.1, lo..hi)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(format!("t ({time_unit})"))
        .y_desc(y_desc)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .y_label_formatter(&tick(hi - lo))
        .x_label_formatter(&tick(t.1 - t.0))
        .draw()
        .map_err(|e| err(&e))?;
    for (points, color, width, label) in series {
        chart
            .draw_series(LineSeries::new(
                thin(points, 400),
                color.stroke_width(width),
            ))
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(width))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    Ok(())
}

/// Draws the figure as SVG text.
///
/// # Errors
/// [`SimulationError::Plot`] when plotters fails.
pub fn svg(
    trace: &Trace,
    states: &[usize],
    title: &str,
    time_unit: &str,
) -> Result<String, SimulationError> {
    let mut text = String::new();
    let err = |e: &dyn std::fmt::Display| SimulationError::Plot(e.to_string());
    {
        let height = 300 * states.len().max(1) as u32 * 2;
        let root = SVGBackend::with_string(&mut text, (800, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        // a title longer than the figure is wide is cut at a word (the caption has it whole)
        let shown = if title.chars().count() > 84 {
            let cut: String = title.chars().take(84).collect();
            format!("{}…", cut.rsplit_once(' ').map_or(cut.as_str(), |(a, _)| a))
        } else {
            title.to_string()
        };
        let root = root
            .titled(&shown, ("sans-serif", 17))
            .map_err(|e| err(&e))?;
        let panels = root.split_evenly((states.len().max(1) * 2, 1));
        let t0 = trace.t.first().copied().unwrap_or(0.0);
        let t1 = trace.t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
        let (blue, red) = (RGBColor(31, 119, 180), RGBColor(214, 39, 40));
        for (k, &s) in states.iter().enumerate() {
            let i = s.saturating_sub(1);
            let column = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
                trace
                    .t
                    .iter()
                    .enumerate()
                    .map(|(j, t)| (*t, f(j)))
                    .collect()
            };
            let truth = column(&|j| trace.x[j][i]);
            let est = column(&|j| trace.xhat[j][i]);
            let error = column(&|j| trace.xhat[j][i] - trace.x[j][i]);
            panel(
                &panels[2 * k],
                (t0, t1),
                &format!("x{s}"),
                time_unit,
                vec![
                    (truth, blue, 2, format!("x{s} (plant)")),
                    (est, red, 2, format!("x̂{s} (observer)")),
                ],
            )?;
            panel(
                &panels[2 * k + 1],
                (t0, t1),
                &format!("e{s} = x̂{s} − x{s}"),
                time_unit,
                vec![(error, BLACK, 1, format!("estimation error e{s}"))],
            )?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(text)
}
