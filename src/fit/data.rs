//! Laboratory data for `stickslip fit`: CSV files with a header row whose
//! column names carry their unit, one file per dataset, each of one kind
//! (seed §II.D.2: how A, B and D0 are measured).
//!
//! | kind | columns | measured |
//! |---|---|---|
//! | `steady` | `V_um_s`, `mu` | steady-state friction against driving velocity |
//! | `onset` | `V_um_s`, `K_over_W_per_m`, optionally `frequency_hz` | the stability boundary `(K/W)_c` and the onset frequency |
//! | `velocity_step` | `t_s`, `V_um_s`, `mu` | friction against time under a protocol of load-point velocities (each row's `V_um_s` holds until the next row's time; steady sliding at the first row's before it) |
//! | `relaxation` | `t_s`, `slip_um`, `V_um_s` | slip after the drive stops at `t = 0`, from steady sliding at `V_um_s` (one velocity per file) |
//!
//! An optional `sigma` column gives each row's measurement error in the
//! measured quantity (`mu`, `K_over_W_per_m` or `slip_um`;
//! `sigma_frequency_hz` for the frequency); without it the error is
//! estimated from the residuals. Times increase strictly from row to row.
//! Lines starting with `#` and blank lines are skipped. Every error names
//! the file, the row (1-based, the header is row 1) and the column.

use crate::error::InputError;
use crate::scene::Law;
use std::path::{Path, PathBuf};

/// What a dataset measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Steady-state friction `mu_ss(V)` (seed eq. RR5).
    Steady,
    /// The onset of stick-slip: `(K/W)_c(V)` (seed eq. KcRR, C11) and,
    /// where measured, its frequency (eq. omegacRR, C13).
    Onset,
    /// Friction `mu(t)` under a protocol of load-point velocities, on the
    /// scene's rig (the spring-block equations of docs/model.md).
    VelocityStep,
    /// Slip `x(t) - x(0)` after the drive stops at `t = 0`, from steady
    /// sliding (seed §II.D.2: the creep-like relaxation).
    Relaxation,
}

impl Kind {
    /// The kinds, by their names on the command line.
    pub const ALL: [(&'static str, Kind); 4] = [
        ("steady", Kind::Steady),
        ("onset", Kind::Onset),
        ("velocity_step", Kind::VelocityStep),
        ("relaxation", Kind::Relaxation),
    ];

    /// The kind named `name`.
    pub fn parse(name: &str) -> Result<Kind, InputError> {
        Kind::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, k)| *k)
            .ok_or_else(|| InputError::UnknownName {
                what: "data kind",
                name: name.to_string(),
                suggestion: crate::error::closest(name, Kind::ALL.iter().map(|(n, _)| *n)),
                allowed: Kind::ALL.map(|(n, _)| n).join(", "),
            })
    }

    /// The kind's name with its article, for messages (`an onset`).
    fn article(self) -> &'static str {
        match self {
            Kind::Steady => "a steady",
            Kind::Onset => "an onset",
            Kind::VelocityStep => "a velocity_step",
            Kind::Relaxation => "a relaxation",
        }
    }

    /// The kind's name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Steady => "steady",
            Kind::Onset => "onset",
            Kind::VelocityStep => "velocity_step",
            Kind::Relaxation => "relaxation",
        }
    }

    /// Whether the dataset is a time series, modelled by integrating the
    /// spring-block equations (`velocity_step`, `relaxation`).
    pub fn is_series(self) -> bool {
        matches!(self, Kind::VelocityStep | Kind::Relaxation)
    }

    /// Required columns, then optional ones, for a scene of `law`; `None`
    /// where the law has no model of this kind.
    fn columns(self, law: Law) -> Option<(&'static [&'static str], &'static [&'static str])> {
        Some(match (law, self) {
            (Law::RateAndState, Kind::Steady) => (&["V_um_s", "mu"], &["sigma"]),
            (Law::RateAndState, Kind::Onset) => (
                &["V_um_s", "K_over_W_per_m"],
                &["frequency_hz", "sigma", "sigma_frequency_hz"],
            ),
            (Law::RateAndState, Kind::VelocityStep) => (&["t_s", "V_um_s", "mu"], &["sigma"]),
            (Law::RateAndState, Kind::Relaxation) => (&["t_s", "slip_um", "V_um_s"], &["sigma"]),
            (Law::Adhesive, Kind::Steady) => (&["V_um_s", "F_N"], &["sigma"]),
            (Law::Adhesive, Kind::Onset) => (&["V_um_s", "K_N_per_m"], &["sigma"]),
            (Law::Adhesive, _) => return None,
        })
    }

    /// The kinds a scene of `law` is fitted to.
    pub fn of_law(law: Law) -> Vec<&'static str> {
        Kind::ALL
            .iter()
            .filter(|(_, k)| k.columns(law).is_some())
            .map(|(n, _)| *n)
            .collect()
    }

    /// Fewest rows a dataset of this kind needs.
    const MIN_ROWS: usize = 2;
}

/// One measured quantity of a dataset: its values and, when the file gives
/// them, their errors.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The column's name (with its unit).
    pub column: &'static str,
    pub values: Vec<f64>,
    pub sigma: Option<Vec<f64>>,
}

/// A dataset read from its file.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    pub kind: Kind,
    pub file: PathBuf,
    /// Driving velocities [µm/s], one per row.
    pub v_um_s: Vec<f64>,
    /// Times \[s\], one per row (time series; empty otherwise).
    pub t_s: Vec<f64>,
    /// The measured quantities: `mu` (steady); `K_over_W_per_m` and, when
    /// given, `frequency_hz` (onset).
    pub measured: Vec<Measured>,
}

impl Dataset {
    /// Reads `file` as a dataset of `kind` for a rate-and-state scene.
    pub fn read(kind: Kind, file: &Path) -> Result<Dataset, InputError> {
        Dataset::read_for(Law::RateAndState, kind, file)
    }

    /// Reads `file` as a dataset of `kind` for a scene of `law`.
    pub fn read_for(law: Law, kind: Kind, file: &Path) -> Result<Dataset, InputError> {
        let text = std::fs::read_to_string(file).map_err(|e| {
            InputError::Conflict(format!(
                "cannot read the {} data file {}: {e}",
                kind.name(),
                file.display()
            ))
        })?;
        Dataset::parse_for(law, kind, file, &text)
    }

    /// Parses `text`, the contents of `file`, for a rate-and-state scene.
    pub fn parse(kind: Kind, file: &Path, text: &str) -> Result<Dataset, InputError> {
        Dataset::parse_for(Law::RateAndState, kind, file, text)
    }

    /// Parses `text`, the contents of `file`, as data of `kind` for a scene
    /// of `law` (an adhesive scene: `steady` in force, `F_N`, and `onset`
    /// as the critical stiffness itself, `K_N_per_m`).
    pub fn parse_for(law: Law, kind: Kind, file: &Path, text: &str) -> Result<Dataset, InputError> {
        let shown = file.display().to_string();
        let (required, optional) = kind.columns(law).ok_or_else(|| {
            InputError::Conflict(format!(
                "{shown}: {} data are fitted on rate-and-state scenes only; an adhesive scene \
                 (law = \"adhesive\") is fitted to {} data",
                kind.name(),
                Kind::of_law(law).join(" and ")
            ))
        })?;
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let Some((header_row, header)) = lines.next() else {
            return Err(malformed(
                &shown,
                "the header",
                "",
                "a header row of column names",
            ));
        };
        // A spreadsheet's "CSV UTF-8" starts with a byte-order mark.
        let header = header.trim_start_matches('\u{feff}');
        if header.contains(';') && !header.contains(',') {
            return Err(malformed(
                &shown,
                &format!("row {header_row} (the header)"),
                header,
                "columns separated by commas (this file separates them by semicolons)",
            ));
        }
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let mut index = Vec::with_capacity(names.len());
        for (c, name) in names.iter().enumerate() {
            let known = required.iter().chain(optional).find(|k| *k == name);
            let Some(known) = known else {
                let allowed = required.iter().chain(optional).copied();
                // A name without its unit (`V` for `V_um_s`), else the closest.
                let hint = allowed
                    .clone()
                    .find(|k| k.split('_').next() == Some(*name))
                    .map(str::to_string)
                    .or_else(|| crate::error::closest(name, allowed.clone()))
                    .map(|k| format!(" (did you mean {k}? a column name carries its unit)"))
                    .unwrap_or_default();
                return Err(malformed(
                    &shown,
                    &format!("row {header_row}, column {}", c + 1),
                    name,
                    &format!(
                        "a column of {} dataset: {}{hint}",
                        kind.article(),
                        allowed.collect::<Vec<_>>().join(", ")
                    ),
                ));
            };
            if index.contains(known) {
                return Err(malformed(
                    &shown,
                    &format!("row {header_row}, column {}", c + 1),
                    name,
                    "each column once",
                ));
            }
            index.push(*known);
        }
        if let Some(missing) = required.iter().find(|r| !index.contains(r)) {
            return Err(malformed(
                &shown,
                &format!("row {header_row} (the header)"),
                header,
                &format!(
                    "a column {missing} ({} dataset needs {})",
                    kind.article(),
                    required.join(", ")
                ),
            ));
        }
        if index.contains(&"sigma_frequency_hz") && !index.contains(&"frequency_hz") {
            return Err(InputError::Conflict(format!(
                "{shown}: a column sigma_frequency_hz without frequency_hz"
            )));
        }
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); index.len()];
        let mut row_numbers = Vec::new();
        for (row, line) in lines {
            row_numbers.push(row);
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != index.len() {
                return Err(malformed(
                    &shown,
                    &format!("row {row}"),
                    line,
                    &format!("{} values ({})", index.len(), index.join(", ")),
                ));
            }
            for (c, (cell, name)) in cells.iter().zip(&index).enumerate() {
                let x: f64 = cell.parse().map_err(|_| {
                    malformed(
                        &shown,
                        &format!("row {row}, column {} ({name})", c + 1),
                        cell,
                        "a number",
                    )
                })?;
                let first = columns[c].is_empty();
                let (ok, expected) = match (*name, kind) {
                    ("mu" | "slip_um", _) => (x.is_finite(), "a finite number"),
                    // The force that resists steady sliding: positive
                    // (a sign-flipped row would be fitted as data).
                    ("F_N", _) => (
                        x.is_finite() && x > 0.0,
                        "a finite friction force > 0 N (the force resisting sliding)",
                    ),
                    ("t_s", Kind::Relaxation) => (
                        x.is_finite() && x >= 0.0,
                        "a finite time >= 0 (the drive stops at t = 0)",
                    ),
                    ("t_s", _) => (x.is_finite(), "a finite number"),
                    // A hold (V = 0) inside a protocol, not at its start.
                    ("V_um_s", Kind::VelocityStep) if !first => {
                        (x.is_finite() && x >= 0.0, "a finite number >= 0")
                    }
                    _ => (x.is_finite() && x > 0.0, "a finite number > 0"),
                };
                if !ok {
                    return Err(InputError::OutOfRange {
                        field: format!("{shown}: row {row}, column {} ({name})", c + 1),
                        value: cell.to_string(),
                        expected: expected.into(),
                    });
                }
                columns[c].push(x);
            }
        }
        let rows = columns[0].len();
        if rows < Kind::MIN_ROWS {
            return Err(InputError::Conflict(format!(
                "{shown}: {rows} data row(s); {} dataset needs at least {}",
                kind.article(),
                Kind::MIN_ROWS
            )));
        }
        let column = |name: &str| {
            index
                .iter()
                .position(|n| *n == name)
                .map(|i| columns[i].clone())
        };
        // Where a check across rows fails: the file, the row, the column.
        let at = |k: usize, name: &str| {
            let c = index.iter().position(|n| *n == name).unwrap_or(0) + 1;
            format!("{shown}: row {}, column {c} ({name})", row_numbers[k])
        };
        if let Some(t) = column("t_s") {
            if let Some(k) = (1..rows).find(|&k| t[k] <= t[k - 1]) {
                return Err(InputError::OutOfRange {
                    field: at(k, "t_s"),
                    value: t[k].to_string(),
                    expected: format!(
                        "a time after the previous row's {} (times increase strictly)",
                        t[k - 1]
                    ),
                });
            }
        }
        if kind == Kind::Relaxation {
            let v = column("V_um_s").unwrap_or_default();
            if let Some(k) = (1..rows).find(|&k| v[k] != v[0]) {
                return Err(InputError::OutOfRange {
                    field: at(k, "V_um_s"),
                    value: v[k].to_string(),
                    expected: format!(
                        "the file's one velocity {} (a relaxation file is one run from steady \
                         sliding: give one file per velocity, --data relaxation=FILE repeated)",
                        v[0]
                    ),
                });
            }
        }
        let measured_column = |name: &'static str, sigma: &str| {
            column(name).map(|values| Measured {
                column: name,
                values,
                sigma: column(sigma),
            })
        };
        // The measured quantities: the required columns after the velocity
        // and the time, then the frequency where given.
        let measured: Vec<_> = required
            .iter()
            .filter(|c| !matches!(**c, "V_um_s" | "t_s"))
            .map(|c| measured_column(c, "sigma"))
            .chain([measured_column("frequency_hz", "sigma_frequency_hz")])
            .collect();
        Ok(Dataset {
            kind,
            file: file.to_path_buf(),
            v_um_s: column("V_um_s").unwrap_or_default(),
            t_s: column("t_s").unwrap_or_default(),
            measured: measured.into_iter().flatten().collect(),
        })
    }

    /// Rows of the file.
    pub fn rows(&self) -> usize {
        self.v_um_s.len()
    }
}

/// A `--data KIND=FILE` option.
pub fn parse_data_option(text: &str) -> Result<(Kind, PathBuf), InputError> {
    let (kind, file) = text.split_once('=').ok_or_else(|| InputError::Malformed {
        field: "--data".into(),
        value: text.into(),
        expected: format!(
            "KIND=FILE with KIND one of {}",
            Kind::ALL.map(|(n, _)| n).join(", ")
        ),
    })?;
    Ok((Kind::parse(kind.trim())?, PathBuf::from(file.trim())))
}

fn malformed(file: &str, at: &str, value: &str, expected: &str) -> InputError {
    InputError::Malformed {
        field: format!("{file}: {at}"),
        value: value.into(),
        expected: expected.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(kind: Kind, text: &str) -> Result<Dataset, String> {
        Dataset::parse(kind, Path::new("d.csv"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn reads_columns_in_any_order_with_comments() {
        let d = parse(
            Kind::Onset,
            "# rig 3\nK_over_W_per_m, V_um_s,frequency_hz\n100,1,0.5\n\n90,10,4\n",
        )
        .unwrap();
        assert_eq!(d.v_um_s, vec![1.0, 10.0]);
        assert_eq!(d.measured[0].values, vec![100.0, 90.0]);
        assert_eq!(d.measured[1].column, "frequency_hz");
        assert!(d.measured[0].sigma.is_none());
    }

    #[test]
    fn bad_data_names_file_row_and_column() {
        let e = parse(Kind::Steady, "V_um_s,mu\n1,0.6\n-2,0.59\n").unwrap_err();
        assert!(e.contains("d.csv: row 3, column 1 (V_um_s)"), "{e}");
        let e = parse(Kind::Steady, "V_um_s,mu\n1,0.6\n2,NaN\n").unwrap_err();
        assert!(e.contains("row 3, column 2 (mu)"), "{e}");
        let e = parse(Kind::Steady, "V_um_s,mu\n1,0.6\n2,x\n").unwrap_err();
        assert!(
            e.contains("row 3, column 2 (mu)") && e.contains("a number"),
            "{e}"
        );
        let e = parse(Kind::Steady, "V,mu\n1,0.6\n").unwrap_err();
        assert!(
            e.contains("d.csv: row 1, column 1: cannot read 'V'") && e.contains("V_um_s"),
            "{e}"
        );
        let e = parse(Kind::Steady, "V_um_s\n1\n2\n").unwrap_err();
        assert!(e.contains("a column mu"), "{e}");
        let e = parse(Kind::Steady, "V_um_s,mu\n1,0.6\n").unwrap_err();
        assert!(e.contains("1 data row(s)"), "{e}");
        let e = parse(Kind::Steady, "V_um_s,mu\n1,0.6\n2\n").unwrap_err();
        assert!(e.contains("row 3") && e.contains("2 values"), "{e}");
        let e = parse(Kind::Steady, "V;mu\n1;0.6\n2;0.5\n").unwrap_err();
        assert!(e.contains("separated by commas"), "{e}");
        let e = parse(Kind::Steady, "V,mu\n1,0.6\n2,0.5\n").unwrap_err();
        assert!(e.contains("did you mean V_um_s?"), "{e}");
        let bom = parse(Kind::Steady, "\u{feff}V_um_s,mu\n1,0.6\n2,0.5\n").unwrap();
        assert_eq!(bom.v_um_s, vec![1.0, 2.0]);
        let e = parse(Kind::Steady, "").unwrap_err();
        assert!(e.contains("header"), "{e}");
        let e = parse_data_option("stedy=x.csv").unwrap_err().to_string();
        assert!(e.contains("did you mean 'steady'"), "{e}");
    }

    #[test]
    fn bad_time_series_name_file_row_and_column() {
        let ok = parse(Kind::VelocityStep, "t_s,V_um_s,mu\n0,1,0.5\n5,10,0.51\n").unwrap();
        assert_eq!(
            (ok.t_s.clone(), ok.measured[0].column),
            (vec![0.0, 5.0], "mu")
        );
        // (kind, file, what the message says)
        let cases: [(Kind, &str, &[&str]); 7] = [
            (
                Kind::VelocityStep,
                "t_s,V_um_s,mu\n0,1,0.5\n0,10,0.51\n",
                &["d.csv: row 3, column 1 (t_s)", "increase"],
            ),
            (
                Kind::VelocityStep,
                "t_s,V_um_s,mu\n0,1,0.5\n1,10,NaN\n",
                &["row 3, column 3 (mu)"],
            ),
            (
                Kind::VelocityStep,
                "t_s,V_um_s,mu\n0,0,0.5\n1,10,0.5\n",
                &["row 2, column 2 (V_um_s)", "> 0"],
            ),
            (
                Kind::VelocityStep,
                "t,V_um_s,mu\n0,1,0.5\n1,10,0.5\n",
                &["did you mean t_s?"],
            ),
            (
                Kind::Relaxation,
                "t_s,slip_um,V_um_s\n0,0,1\n1,0.1,1\n2,0.2,3\n",
                &["row 4, column 3 (V_um_s)", "one file per velocity"],
            ),
            (
                Kind::Relaxation,
                "t_s,slip\n0,0\n1,0.1\n",
                &["did you mean slip_um?"],
            ),
            (
                Kind::Relaxation,
                "t_s,slip_um,V_um_s\n-1,0,1\n1,0.1,1\n",
                &["row 2, column 1 (t_s)", ">= 0"],
            ),
        ];
        for (kind, text, says) in cases {
            let e = parse(kind, text).unwrap_err();
            assert!(says.iter().all(|s| e.contains(s)), "{e}");
        }
    }
}
