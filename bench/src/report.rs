//! The measurements as JSON records and as a text table.

use super::measure::JobReport;
use continuation::EVAL_KINDS;
use serde_json::{json, Value};

impl JobReport {
    /// The JSON record: `job`, `median_s`, `points`, `per_point_s`,
    /// `repetitions`, `evals` (by kind), plus `min_s`, `max_s`, `description`,
    /// and for a cycle branch `accuracy` (its last cycle against integration).
    pub fn to_json(&self) -> Value {
        let evals: serde_json::Map<String, Value> = EVAL_KINDS
            .iter()
            .zip(self.evals)
            .map(|(k, n)| (k.to_string(), json!(n)))
            .collect();
        let mut v = json!({
            "job": self.job,
            "description": self.description,
            "median_s": self.median_s,
            "min_s": self.min_s,
            "max_s": self.max_s,
            "points": self.points,
            "per_point_s": self.per_point_s,
            "repetitions": self.repetitions,
            "evals": evals,
        });
        if let Some(a) = &self.accuracy {
            v["accuracy"] = json!({
                "kappa": a.kappa,
                "period": a.period,
                "period_reference": a.period_reference,
                "period_rel_error": a.period_error,
                "delta_s_rel_error": a.delta_s_error,
                "reference_spread": a.reference_spread,
                "reference": super::REFERENCE,
            });
        }
        v
    }
}

/// The reports as a JSON array, one record per job.
pub fn to_json(reports: &[JobReport]) -> Value {
    Value::Array(reports.iter().map(JobReport::to_json).collect())
}

/// A duration in seconds with a unit that keeps 3–4 significant digits.
pub fn format_seconds(s: f64) -> String {
    match s {
        _ if s >= 1.0 => format!("{s:.3} s"),
        _ if s >= 1e-3 => format!("{:.3} ms", s * 1e3),
        _ if s >= 1e-6 => format!("{:.2} us", s * 1e6),
        _ => format!("{:.0} ns", s * 1e9),
    }
}

/// The reports as an aligned text table.
pub fn table(reports: &[JobReport]) -> String {
    let mut header = vec![
        "job".to_string(),
        "median".into(),
        "min".into(),
        "reps".into(),
        "points".into(),
        "per point".into(),
    ];
    header.extend(EVAL_KINDS.iter().map(|k| format!("evals {k}")));
    header.push("period err".into());
    let rows: Vec<Vec<String>> = reports
        .iter()
        .map(|r| {
            let mut row = vec![
                r.job.to_string(),
                format_seconds(r.median_s),
                format_seconds(r.min_s),
                r.repetitions.to_string(),
                r.points.to_string(),
                format_seconds(r.per_point_s),
            ];
            row.extend(r.evals.iter().map(u64::to_string));
            row.push(
                r.accuracy
                    .as_ref()
                    .map_or("-".into(), |a| format!("{:.1e}", a.period_error)),
            );
            row
        })
        .collect();
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            std::iter::once(&header)
                .chain(&rows)
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |cells: &[String]| {
        cells
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, &w))| {
                if c == 0 {
                    format!("{cell:<w$}")
                } else {
                    format!("{cell:>w$}")
                }
            })
            .collect::<Vec<_>>()
            .join("  ")
    };
    let mut out = line(&header);
    out.push('\n');
    for r in &rows {
        out.push_str(&line(r));
        out.push('\n');
    }
    out
}
