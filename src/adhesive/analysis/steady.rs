//! Steady sliding of the adhesive block across driving velocities: the
//! branch at the scene's stiffness (eigenvalues, the Hopf points where it
//! changes stability, located in `nu` by the engine), and the stability
//! diagram, the critical stiffness at each velocity located by the engine
//! (Newton's method on the Hopf system from the closed form), with the
//! onset type. Steady sliding is explicit (`u = nu`, `n = n_ss(nu)`,
//! `s = F_ss(nu)`, eq. D2), so both sample a grid in `ln nu`.

use crate::adhesive::block::{self, AdhesiveModel};
use crate::adhesive::params::{AdhesiveParam, AdhesiveParams};
use crate::analysis::hopf::{onset_at, Criticality};
use crate::error::NumericalError;
use continuation::locate_hopf;
use continuation::system::jacobian;
use continuation::{count_unstable, eigenvalues};
use continuation::{EventKind, NewtonSettings};

/// A point of steady sliding, dimensionless.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SteadyPoint {
    pub nu: f64,
    /// Spring force (steady friction) `F_ss / F_a`.
    pub s: f64,
    /// Bond fraction `n_ss`.
    pub n: f64,
    /// `dF_ss / du`.
    pub slope: f64,
    /// Eigenvalues at the given stiffness, `[re, im]`, by decreasing real part.
    pub eigenvalues: Vec<[f64; 2]>,
    pub stable: bool,
}

/// A Hopf point of the steady branch in `nu` at fixed stiffness.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct NuHopf {
    pub nu: f64,
    pub omega: f64,
}

/// The velocity grid: `points_per_decade` in `ln nu` over `[lo, hi]`.
pub fn grid(lo: f64, hi: f64, points_per_decade: usize) -> Vec<f64> {
    let n = ((hi / lo).log10() * points_per_decade as f64)
        .ceil()
        .max(1.0) as usize;
    (0..=n)
        .map(|i| lo * (hi / lo).powf(i as f64 / n as f64))
        .collect()
}

/// Steady sliding at every `nu` of `nus` at the stiffness of `p`, and the
/// Hopf points between grid points where stability changes.
pub fn branch<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    nus: &[f64],
) -> Result<(Vec<SteadyPoint>, Vec<NuHopf>), NumericalError> {
    let mut points: Vec<SteadyPoint> = Vec::new();
    let mut hopfs = Vec::new();
    for &nu in nus {
        let mut q = *p;
        q.nu = nu;
        let x = model.steady(&q);
        let ev = eigenvalues(&jacobian(&model, &x, &q.to_vec()))?;
        let point = SteadyPoint {
            nu,
            s: x[0],
            n: model.bonds(&x),
            slope: block::steady_slope(nu, &q),
            eigenvalues: ev.iter().map(|e| [e.re, e.im]).collect(),
            stable: count_unstable(&ev) == 0,
        };
        // Without a spring (a scene with no K) steady sliding changes
        // stability where the friction slope changes sign: a zero
        // eigenvalue, no Hopf point to locate.
        if let Some(prev) = points
            .last()
            .filter(|prev| prev.stable != point.stable && q.kappa > 0.0)
        {
            let mut mid = q;
            mid.nu = (prev.nu * nu).sqrt();
            let (_, omega) = block::critical_stiffness_of(&mid, B::KIND);
            let omega = if omega.is_finite() {
                omega
            } else {
                ev[0].im.abs()
            };
            let located = locate_hopf(
                &model,
                AdhesiveParam::Nu as usize,
                &model.steady(&mid),
                &mid.to_vec(),
                omega,
                &NewtonSettings::default(),
            )?;
            if let EventKind::Hopf { omega } = located.kind {
                hopfs.push(NuHopf {
                    nu: located.point.param(),
                    omega,
                });
            }
        }
        points.push(point);
    }
    Ok((points, hopfs))
}

/// The onset at one driving velocity.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DiagramPoint {
    pub nu: f64,
    /// Critical stiffness located by the engine; `None` where steady
    /// friction rises with the velocity (stable at every stiffness).
    pub kappa_c: Option<f64>,
    pub omega_c: Option<f64>,
    pub onset: Option<Criticality>,
    pub l1: Option<f64>,
    /// The inertia ratio `chi = m lambda_n / F_u` here
    /// ([`block::inertia_ratio`]), and whether the inertial model is
    /// needed here (`chi` not below the threshold; `diagram` adds where
    /// inertia changes the onset type): what `hopf` at this velocity decides.
    pub inertia_ratio: f64,
    pub needs_inertia: bool,
}

/// The stability diagram of `model` over `nus`, each point with its
/// inertia ratio against `threshold`.
pub fn diagram<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    nus: &[f64],
    threshold: f64,
) -> Result<Vec<DiagramPoint>, NumericalError> {
    nus.iter()
        .map(|&nu| {
            let mut q = *p;
            q.nu = nu;
            let inertia_ratio = block::inertia_ratio(&q);
            let needs_inertia =
                block::model_for(&q, threshold) == crate::model::ModelKind::Inertial;
            let (closed, omega) = block::critical_stiffness_of(&q, B::KIND);
            if closed.is_nan() || closed <= 0.0 {
                return Ok(DiagramPoint {
                    nu,
                    kappa_c: None,
                    omega_c: None,
                    onset: None,
                    l1: None,
                    inertia_ratio,
                    needs_inertia,
                });
            }
            q.kappa = closed;
            let e = locate_hopf(
                &model,
                AdhesiveParam::Kappa as usize,
                &model.steady(&q),
                &q.to_vec(),
                omega,
                &NewtonSettings::default(),
            )?;
            let EventKind::Hopf { omega } = e.kind else {
                return Err(NumericalError::Analysis(format!(
                    "no Hopf point located at nu = {nu:e}"
                )));
            };
            let error = (e.point.param() - closed)
                .abs()
                .max(4.0 * f64::EPSILON * closed);
            let nf = onset_at(&model, &e.point.x, &e.point.p, omega, error)?;
            Ok(DiagramPoint {
                nu,
                kappa_c: Some(e.point.param()),
                omega_c: Some(omega),
                onset: Some(nf.criticality),
                l1: Some(nf.l1),
                inertia_ratio,
                needs_inertia,
            })
        })
        .collect()
}

/// A change of the onset type between two velocities of the diagram's grid
/// (a Bautin point, `l1 = 0`), located by bisection in `ln nu`.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Bautin {
    /// The last velocity bisected, and its critical stiffness.
    pub nu: f64,
    pub kappa_c: f64,
    /// The bracket left: the onset type is `below`'s at `nu_low` and
    /// `above`'s at `nu_high`.
    pub nu_low: f64,
    pub nu_high: f64,
    pub below: Criticality,
    pub above: Criticality,
}

/// Locates the change of the onset type between the diagram points `a` and
/// `b` (their onsets of different types) by bisection in `ln nu`, down to
/// a bracket of relative width `1e-9` or to a midpoint whose type is
/// degenerate (`l1 = 0` within its error: the Bautin point to rounding).
pub fn bautin<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    (a, b): (&DiagramPoint, &DiagramPoint),
) -> Result<Option<Bautin>, NumericalError> {
    let (Some(below), Some(above), Some(mut kappa_c)) = (a.onset, b.onset, a.kappa_c) else {
        return Ok(None);
    };
    let (mut lo, mut hi, mut nu) = (a.nu, b.nu, a.nu);
    while hi / lo > 1.0 + 1e-9 {
        nu = (lo * hi).sqrt();
        let Some(mid) = diagram(model, p, &[nu], f64::INFINITY)?.pop() else {
            break;
        };
        let (Some(onset), Some(k)) = (mid.onset, mid.kappa_c) else {
            break;
        };
        kappa_c = k;
        if onset == below {
            lo = nu;
        } else if onset == above {
            hi = nu;
        } else {
            break;
        }
    }
    Ok(Some(Bautin {
        nu,
        kappa_c,
        nu_low: lo,
        nu_high: hi,
        below,
        above,
    }))
}
