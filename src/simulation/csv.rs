//! Time series as CSV: `t, x1…, xhat1…, e1…, y1…, u1…`, full `f64` precision (shortest
//! round-trip formatting), so equal runs give byte-identical files.

use super::run::Trace;
use std::fmt::Write;

/// The CSV text of a run.
pub fn to_csv(trace: &Trace) -> String {
    let (n, p, m) = (trace.x.width(), trace.y.width(), trace.u.width());
    let mut header = vec!["t".to_string()];
    header.extend((1..=n).map(|i| format!("x{i}")));
    header.extend((1..=n).map(|i| format!("xhat{i}")));
    header.extend((1..=n).map(|i| format!("e{i}")));
    header.extend((1..=p).map(|i| format!("y{i}")));
    header.extend((1..=m).map(|i| format!("u{i}")));
    let mut out = header.join(",");
    out.push('\n');
    for k in 0..trace.t.len() {
        let _ = write!(out, "{}", trace.t[k]);
        for v in trace.x[k].iter().chain(&trace.xhat[k][..]) {
            let _ = write!(out, ",{v}");
        }
        for i in 0..n {
            let _ = write!(out, ",{}", trace.xhat[k][i] - trace.x[k][i]);
        }
        for v in trace.y[k].iter().chain(&trace.u[k][..]) {
            let _ = write!(out, ",{v}");
        }
        out.push('\n');
    }
    out
}
