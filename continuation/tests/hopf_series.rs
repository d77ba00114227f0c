//! Fifth-order Hopf normal form against the Bautin normal form, whose
//! coefficients are known, before and after a nonlinear change of coordinates.

use continuation::normal_form::hopf_normal_form;
use continuation::normal_form::hopf_series;
use continuation::{Scalar, VectorField};

/// `Z' = i w Z + c1 Z |Z|^2 + c2 Z |Z|^4` in `x = (Re Z, Im Z)`, seen through the
/// near-identity change of coordinates `x = y + (a y0^2, b y0 y1)` when `warp`.
/// With the unit eigenvector `(1, -i)/sqrt 2`, `Z = sqrt 2 z`, so the normal form
/// in `z` has `2 c1` and `4 c2`: `l1 = 2 Re(c1)/w`, `l2 = 4 Re(c2)/w`.
struct Bautin {
    w: f64,
    c1: (f64, f64),
    c2: (f64, f64),
    warp: Option<(f64, f64)>,
}

impl Bautin {
    fn field<D: Scalar>(&self, x: [D; 2]) -> [D; 2] {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let r4 = r2 * r2;
        let re = (
            r2 * self.c1.0 + r4 * self.c2.0,
            r2 * self.c1.1 + r4 * self.c2.1,
        );
        [
            x[0] * re.0 - x[1] * (re.1 + self.w),
            x[0] * (re.1 + self.w) + x[1] * re.0,
        ]
    }
}

impl VectorField for Bautin {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        0
    }
    fn rhs<D: Scalar>(&self, y: &[D], _: &[D], out: &mut [D]) {
        let Some((a, b)) = self.warp else {
            let f = self.field([y[0], y[1]]);
            out.copy_from_slice(&f);
            return;
        };
        // x = psi(y); y' = (D psi)^-1 f(psi(y)), D psi = [[1 + 2 a y0, 0], [b y1, 1 + b y0]].
        let x = [y[0] + y[0] * y[0] * a, y[1] + y[0] * y[1] * b];
        let f = self.field(x);
        let d00 = y[0] * (2.0 * a) + 1.0;
        let (d10, d11) = (y[1] * b, y[0] * b + 1.0);
        let y0dot = f[0] / d00;
        out[0] = y0dot;
        out[1] = (f[1] - d10 * y0dot) / d11;
    }
}

#[test]
fn l2_of_the_bautin_normal_form() {
    for warp in [None, Some((0.8, -1.3))] {
        let (w, c1, c2) = (1.7, (0.0, 0.45), (-0.4, 0.3));
        let sys = Bautin { w, c1, c2, warp };
        let s = hopf_series(&sys, &[0.0, 0.0], &[], w).unwrap();
        assert!(s.l1.abs() < 1e-14, "{warp:?}: l1 = {}", s.l1);
        assert!(
            (s.l2 / (4.0 * c2.0 / w) - 1.0).abs() < 1e-12,
            "{warp:?}: l2 = {} vs {}",
            s.l2,
            4.0 * c2.0 / w
        );
        if warp.is_none() {
            assert!((s.c1.im - 2.0 * c1.1).abs() < 1e-13 && (s.c2.im - 4.0 * c2.1).abs() < 1e-12);
        }
    }
}

#[test]
fn series_l1_equals_the_closed_formula() {
    // With Re c1 != 0 and a warp, the series and Kuznetsov's formula must agree on l1.
    let sys = Bautin {
        w: 0.9,
        c1: (-0.35, 0.2),
        c2: (0.1, 0.0),
        warp: Some((0.5, 0.7)),
    };
    let s = hopf_series(&sys, &[0.0, 0.0], &[], 0.9).unwrap();
    let nf = hopf_normal_form(&sys, &[0.0, 0.0], &[], 0.9).unwrap();
    assert!((s.l1 / nf.l1 - 1.0).abs() < 1e-13 && (s.l1 / (2.0 * -0.35 / 0.9) - 1.0).abs() < 1e-13);
    assert!((s.c1 - nf.c1).norm() < 1e-13);
}
