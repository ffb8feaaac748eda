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
        let root = root
            .titled(title, ("sans-serif", 20))
            .map_err(|e| err(&e))?;
        let panels = root.split_evenly((states.len().max(1) * 2, 1));
        let t0 = trace.t.first().copied().unwrap_or(0.0);
        let t1 = trace.t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
        let colors = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];
        for (k, &s) in states.iter().enumerate() {
            let i = s.saturating_sub(1);
            let truth: Vec<(f64, f64)> = trace
                .t
                .iter()
                .zip(&trace.x)
                .map(|(t, x)| (*t, x[i]))
                .collect();
            let est: Vec<(f64, f64)> = trace
                .t
                .iter()
                .zip(&trace.xhat)
                .map(|(t, x)| (*t, x[i]))
                .collect();
            let error: Vec<(f64, f64)> = trace
                .t
                .iter()
                .zip(trace.x.iter().zip(&trace.xhat))
                .map(|(t, (x, xh))| (*t, xh[i] - x[i]))
                .collect();
            let (lo, hi) = range(truth.iter().chain(&est).map(|p| p.1));
            let mut chart = ChartBuilder::on(&panels[2 * k])
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(t0..t1, lo..hi)
                .map_err(|e| err(&e))?;
            chart
                .configure_mesh()
                .x_desc(format!("t ({time_unit})"))
                .y_desc(format!("x{s}"))
                .draw()
                .map_err(|e| err(&e))?;
            chart
                .draw_series(LineSeries::new(truth, colors[0].stroke_width(2)))
                .map_err(|e| err(&e))?
                .label(format!("x{s} (plant)"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colors[0].stroke_width(2))
                });
            chart
                .draw_series(LineSeries::new(est, colors[1].stroke_width(2)))
                .map_err(|e| err(&e))?
                .label(format!("x̂{s} (observer)"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colors[1].stroke_width(2))
                });
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| err(&e))?;
            let (lo, hi) = range(error.iter().map(|p| p.1));
            let mut chart = ChartBuilder::on(&panels[2 * k + 1])
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(t0..t1, lo..hi)
                .map_err(|e| err(&e))?;
            chart
                .configure_mesh()
                .x_desc(format!("t ({time_unit})"))
                .y_desc(format!("e{s} = x̂{s} − x{s}"))
                .draw()
                .map_err(|e| err(&e))?;
            chart
                .draw_series(LineSeries::new(error, BLACK.stroke_width(1)))
                .map_err(|e| err(&e))?
                .label(format!("estimation error e{s}"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(text)
}
