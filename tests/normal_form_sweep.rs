//! Normal-form coefficients over 17 decades of inertia (m = 1e-14 .. 1e3) on
//! the three friction laws, against the high-precision references of
//! `docs/reference/m_sweep.csv` (sympy-exact derivatives, mpmath at 90+
//! digits, three independent routes; `docs/reference/m_sweep.md`).
//!
//! What is checked, row by row:
//! * the reported error bounds bracket the truth: `|l1 - l1_ref| <= l1_error_bound`,
//!   `|l2 - l2_ref| <= l2_error_bound`;
//! * the onset type is right, or honestly "degenerate" (never a wrong sign);
//! * the bound claims six digits on every row, so they are there (implied by
//!   bracketing), including the plain RR law at `m = 1e-14`, where the terms
//!   of `l1` cancel by a factor 1e13 and double-double takes over;
//! * `C` (peak-to-peak `Delta_s ~ C sqrt|kappa - kappa_c|`) to the relative
//!   accuracy of `l1` (it goes as `|l1|^-1/2`).

use stickslip::analysis::hopf::{find_hopf, second_lyapunov, Criticality, HopfOutcome};
use stickslip::model::ModelKind;
use stickslip::params::Params;

struct Row {
    label: String,
    params: Params,
    l1: f64,
    l2: f64,
    c: f64,
}

fn rows() -> Vec<Row> {
    let text = include_str!("../docs/reference/m_sweep.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |name: &str| f[col(name)].parse::<f64>().unwrap();
            let theta_c = f[col("theta_c")];
            let params = Params {
                kappa: 0.0,
                nu: num("nu"),
                m: num("m"),
                a: num("A"),
                b: num("B"),
                mu0: num("mu0"),
                mu2: num("mu2"),
                theta_c: (!theta_c.is_empty()).then(|| theta_c.parse().unwrap()),
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            };
            Row {
                label: format!(
                    "{} A={} nu={} m={}",
                    f[col("law")],
                    f[col("A")],
                    f[col("nu")],
                    f[col("m")]
                ),
                params,
                l1: num("l1"),
                l2: num("l2"),
                c: num("C"),
            }
        })
        .collect()
}

#[test]
fn error_bounds_bracket_the_high_precision_normal_forms() {
    let rows = rows();
    assert!(rows.len() >= 50, "{} rows", rows.len());
    let mut failed = Vec::new();
    for r in &rows {
        let h = match find_hopf(ModelKind::Inertial, &r.params) {
            Ok(HopfOutcome::Found(h)) => h,
            Ok(other) => panic!("{}: {other:?}", r.label),
            Err(e) => {
                eprintln!("{}: {e}", r.label);
                failed.push(r.label.clone());
                continue;
            }
        };
        let o = &h.onset;
        let err = (o.l1 - r.l1).abs();
        assert!(
            err <= o.l1_error_bound,
            "{}: l1 = {:e}, reference {:e}, error {err:.2e} above its bound {:.2e}",
            r.label,
            o.l1,
            r.l1,
            o.l1_error_bound
        );
        // Right sign or degenerate, never a wrong sign.
        let expected = if r.l1 < 0.0 {
            Criticality::Supercritical
        } else {
            Criticality::Subcritical
        };
        assert!(
            o.criticality == expected || o.criticality == Criticality::Degenerate,
            "{}: {:?} for l1 = {:e}",
            r.label,
            o.criticality,
            r.l1
        );
        let claims_six_digits = o.l1_error_bound <= 1e-6 * r.l1.abs();
        eprintln!(
            "{:<40} l1 = {:+.10e}  error {:.1e}  bound {:.1e}  {:?}",
            r.label,
            o.l1,
            err / r.l1.abs(),
            o.l1_error_bound / r.l1.abs(),
            o.criticality
        );
        // Six digits everywhere: where f64 cancels them away (plain RR law
        // at small m) the normal form is recomputed in double-double.
        assert!(
            claims_six_digits,
            "{}: bound {:.2e} on l1 = {:e} does not claim six digits ({})",
            r.label,
            o.l1_error_bound,
            r.l1,
            o.arithmetic.name()
        );
        if o.criticality != Criticality::Degenerate {
            let c = o.amplitude_coefficient.unwrap();
            let rel = (c / r.c - 1.0).abs();
            // C ~ |l1|^(-1/2): half the relative bound of l1, plus rounding.
            let tol = 0.5 * o.l1_error_bound / o.l1.abs() + 1e-12;
            assert!(
                rel <= 2.0 * tol,
                "{}: C = {c:e}, reference {:e}, rel {rel:.1e} (tol {tol:.1e})",
                r.label,
                r.c
            );
        }
        let (l2, l2_bound) = second_lyapunov(ModelKind::Inertial, &r.params, &h).unwrap();
        let err2 = (l2 - r.l2).abs();
        assert!(
            err2 <= l2_bound,
            "{}: l2 = {l2:e}, reference {:e}, error {err2:.2e} above its bound {l2_bound:.2e}",
            r.label,
            r.l2,
        );
    }
    assert!(failed.is_empty(), "onset not found: {failed:?}");
}
