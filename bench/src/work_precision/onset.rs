//! Work against precision at the stick-slip onset: `kappa_c` against the
//! Newton tolerance of the Hopf location (reference: eq. C12), and `l1` by
//! exact multilinear forms against finite differences (reference: the
//! quasi-static ln² closed form).

use super::{methods, points, render_figure, time_it, Measurement};
use continuation::eigenpair_near;
use continuation::normal_form::hopf_normal_form;
use continuation::system::{eval, jacobian};
use continuation::AsIs;
use continuation::{Complex64, NewtonSettings, VectorField};
use nalgebra::{DMatrix, DVector};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};
use stickslip::analysis::hopf::{find_hopf_with, HopfOutcome};
use stickslip::error::{Error, NumericalError};
use stickslip::model::{DrivenBlock, ModelKind};
use stickslip::params::Params;
use stickslip::plot::lines::{LineFigure, Series};

/// `l1` by Kuznetsov's formula with `B` and `C` from central finite
/// differences of `f` with step `h` (truncation `O(h^2)`, rounding `O(eps/h^3)`):
/// the method AUTO-07p and MatCont use, here for comparison only.
pub fn l1_finite_differences<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
    h: f64,
) -> Result<f64, NumericalError> {
    let n = x.len();
    let f = |dx: &[f64]| {
        let y: Vec<f64> = (0..n).map(|i| x[i] + dx[i]).collect();
        eval(sys, &y, p)
    };
    let comb = |terms: &[(f64, &[f64])]| -> Vec<f64> {
        (0..n)
            .map(|i| terms.iter().map(|(c, v)| c * v[i]).sum())
            .collect()
    };
    let b_real = |u: &[f64], v: &[f64]| {
        let t = |su: f64, sv: f64| f(&comb(&[(su * h, u), (sv * h, v)]));
        (t(1.0, 1.0) - t(1.0, -1.0) - t(-1.0, 1.0) + t(-1.0, -1.0)) / (4.0 * h * h)
    };
    let c_real = |u: &[f64], v: &[f64], w: &[f64]| {
        let mut acc = DVector::zeros(n);
        for mask in 0..8u32 {
            let s = |bit: u32| if mask >> bit & 1 == 0 { 1.0 } else { -1.0 };
            acc += f(&comb(&[(s(0) * h, u), (s(1) * h, v), (s(2) * h, w)])) * (s(0) * s(1) * s(2));
        }
        acc / (8.0 * h * h * h)
    };
    let split = |z: &DVector<Complex64>| {
        [
            (z.map(|c| c.re), Complex64::new(1.0, 0.0)),
            (z.map(|c| c.im), Complex64::new(0.0, 1.0)),
        ]
    };
    let b = |u: &DVector<Complex64>, v: &DVector<Complex64>| {
        let mut out = DVector::from_element(n, Complex64::new(0.0, 0.0));
        for (ur, cu) in split(u) {
            for (vr, cv) in split(v) {
                out += b_real(ur.as_slice(), vr.as_slice()).map(|t| cu * cv * t);
            }
        }
        out
    };
    let c = |u: &DVector<Complex64>, v: &DVector<Complex64>, w: &DVector<Complex64>| {
        let mut out = DVector::from_element(n, Complex64::new(0.0, 0.0));
        for (ur, cu) in split(u) {
            for (vr, cv) in split(v) {
                for (wr, cw) in split(w) {
                    out += c_real(ur.as_slice(), vr.as_slice(), wr.as_slice())
                        .map(|t| cu * cv * cw * t);
                }
            }
        }
        out
    };
    let a = jacobian(sys, x, p);
    let iw = Complex64::new(0.0, omega);
    // The phase of q fixed (its largest entry real and positive): the
    // differences below step along Re q and Im q, so their truncation and
    // rounding depend on it, and this way not on the eigenvalue routine.
    let (_, q) = eigenpair_near(&a, iw)?;
    let largest = q
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .filter(|z| z.norm() > 0.0)
        .unwrap_or(Complex64::new(1.0, 0.0));
    let q = &q * (largest.conj() / largest.norm());
    let (_, pt) = eigenpair_near(&a.transpose(), -iw)?;
    let padj = &pt / pt.dotc(&q).conj();
    let qb = q.map(|z| z.conj());
    let ac = a.map(Complex64::from);
    let singular =
        || NumericalError::Analysis("singular matrix in the finite-difference l1".into());
    let h11 = ac.clone().lu().solve(&b(&q, &qb)).ok_or_else(singular)?;
    let h20 = (DMatrix::identity(n, n) * Complex64::new(0.0, 2.0 * omega) - ac)
        .lu()
        .solve(&b(&q, &q))
        .ok_or_else(singular)?;
    let c1 =
        padj.dotc(&c(&q, &q, &qb)) * 0.5 - padj.dotc(&b(&q, &h11)) + padj.dotc(&b(&qb, &h20)) * 0.5;
    Ok(c1.re / omega)
}

/// Runs the study on the PMMA scene (quasi-static ln² law at 1 um/s).
pub(super) fn study() -> Result<Vec<Measurement>, Error> {
    let p = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 0.0,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 2.4e-4,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let kind = ModelKind::QuasiStatic;
    let mut out = Vec::new();
    // kappa_c against C12 as the Newton tolerance of the location varies.
    let kappa_ref = p.mu_phi() - p.mu_v();
    for tol in [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
        let locator = NewtonSettings {
            step_tol: tol,
            residual_tol: tol,
            max_iter: 30,
        };
        let HopfOutcome::Found(h) = find_hopf_with(&AsIs, kind, &p, &locator)? else {
            return Err(NumericalError::Analysis(
                "no Hopf point in the work-precision scene".into(),
            )
            .into());
        };
        let seconds = time_it(|| find_hopf_with(&AsIs, kind, &p, &locator));
        let error = ((h.kappa_c - kappa_ref) / kappa_ref).abs().max(1e-17);
        out.push(Measurement {
            job: "kappa_c",
            method: "continuation + Newton (tolerance)".into(),
            knob: tol,
            seconds,
            error,
        });
    }
    // l1 at the onset: exact forms against finite differences.
    let HopfOutcome::Found(h) = find_hopf_with(
        &AsIs,
        kind,
        &p,
        &NewtonSettings {
            step_tol: 1e-14,
            residual_tol: 1e-12,
            max_iter: 20,
        },
    )?
    else {
        return Err(
            NumericalError::Analysis("no Hopf point in the work-precision scene".into()).into(),
        );
    };
    let block = DrivenBlock::new(kind, &p);
    let mut at = p;
    at.kappa = h.kappa_c;
    let (x, pv) = ([h.state[0], h.state[2]], at.to_vec());
    let mu_phi = p.mu_phi();
    let d = 1.0 + mu_phi * (mu_phi - p.a);
    let l1_ref = -p.mu2 / (2.0 * (p.a * (mu_phi - p.a)).sqrt() * d);
    let exact = hopf_normal_form(&block, &x, &pv, h.omega_c)
        .map_err(NumericalError::from)?
        .l1;
    out.push(Measurement {
        job: "l1",
        method: "exact (dual numbers)".into(),
        knob: 0.0,
        seconds: time_it(|| hopf_normal_form(&block, &x, &pv, h.omega_c)),
        error: ((exact - l1_ref) / l1_ref).abs().max(1e-17),
    });
    for step in [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5] {
        let l1 = l1_finite_differences(&block, &x, &pv, h.omega_c, step)?;
        let seconds = time_it(|| l1_finite_differences(&block, &x, &pv, h.omega_c, step));
        out.push(Measurement {
            job: "l1",
            method: "finite differences (step h)".into(),
            knob: step,
            seconds,
            error: ((l1 - l1_ref) / l1_ref).abs(),
        });
    }
    Ok(out)
}

/// The figures of the onset jobs: error against time for `kappa_c` and `l1`,
/// and the finite-difference error of `l1` against its step.
pub(super) fn figures(measurements: &[Measurement], out: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut files = Vec::new();
    let colors = [RGBColor(31, 90, 180), RGBColor(200, 40, 40)];
    for (job, title) in [
        ("kappa_c", "kappa_c against eq. C12"),
        ("l1", "first Lyapunov coefficient against its closed form"),
    ] {
        let series = methods(measurements, job)
            .iter()
            .enumerate()
            .map(|(i, method)| Series {
                label: Some(method.to_string()),
                points: points(measurements, job, method),
                color: colors[i % colors.len()],
                dashed: false,
                markers: true,
            })
            .collect();
        let fig = LineFigure {
            title: format!("Work against precision: {title} (PMMA onset)"),
            x_label: "time per evaluation [s]".into(),
            y_label: "relative error".into(),
            log_x: true,
            log_y: true,
            series,
        };
        files.extend(render_figure(&fig, out, job)?);
    }
    // Finite differences against their step: truncation O(h^2) on the right,
    // rounding O(eps / h^3) on the left; the exact value as a reference line.
    let fd: Vec<(f64, f64)> = measurements
        .iter()
        .filter(|m| m.job == "l1" && m.knob > 0.0)
        .map(|m| (m.knob, m.error))
        .collect();
    if let (Some(exact), Some(lo), Some(hi)) = (
        measurements.iter().find(|m| m.job == "l1" && m.knob == 0.0),
        fd.iter().map(|p| p.0).reduce(f64::min),
        fd.iter().map(|p| p.0).reduce(f64::max),
    ) {
        let fig = LineFigure {
            title: "First Lyapunov coefficient: finite-difference step against error".into(),
            x_label: "finite-difference step h".into(),
            y_label: "relative error of l1".into(),
            log_x: true,
            log_y: true,
            series: vec![
                Series {
                    label: Some("finite differences".into()),
                    points: fd,
                    color: colors[1],
                    dashed: false,
                    markers: true,
                },
                Series {
                    label: Some("exact (dual numbers)".into()),
                    points: vec![(lo, exact.error), (hi, exact.error)],
                    color: colors[0],
                    dashed: true,
                    markers: false,
                },
            ],
        };
        files.extend(render_figure(&fig, out, "l1-step")?);
    }
    Ok(files)
}
