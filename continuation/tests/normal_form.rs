//! Normal-form coefficients against the Hopf normal form, whose answers are known.

use continuation::normal_form::{eigenvalue_derivative, hopf_normal_form, onset_law};
use continuation::{Scalar, VectorField};

/// Stuart–Landau `Z' = (beta + i w) Z + c Z |Z|^2`, `beta = p - p0`, written in
/// real coordinates `y = T (Re Z, Im Z)` for an invertible `T`.
struct StuartLandau {
    w: f64,
    c: (f64, f64),
    t: [[f64; 2]; 2],
}

impl VectorField for StuartLandau {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, y: &[D], p: &[D], out: &mut [D]) {
        let [[a, b], [c, d]] = self.t;
        let det = a * d - b * c;
        // (x0, x1) = T^-1 y
        let x0 = (y[0] * d - y[1] * b) / det;
        let x1 = (y[1] * a - y[0] * c) / det;
        let r2 = x0 * x0 + x1 * x1;
        let f0 = p[0] * x0 - x1 * self.w + (x0 * self.c.0 - x1 * self.c.1) * r2;
        let f1 = x0 * self.w + p[0] * x1 + (x0 * self.c.1 + x1 * self.c.0) * r2;
        out[0] = f0 * a + f1 * b;
        out[1] = f0 * c + f1 * d;
    }
}

#[test]
fn stuart_landau_l1_is_two_re_c_over_w_with_a_unit_eigenvector() {
    for (w, c) in [(1.0, (-1.0, 0.0)), (2.5, (-0.3, 0.7)), (0.4, (0.8, -2.0))] {
        let sys = StuartLandau {
            w,
            c,
            t: [[1.0, 0.0], [0.0, 1.0]],
        };
        let nf = hopf_normal_form(&sys, &[0.0, 0.0], &[0.0], w).unwrap();
        assert!(
            (nf.l1 / (2.0 * c.0 / w) - 1.0).abs() < 1e-13,
            "l1 = {} for c = {c:?}",
            nf.l1
        );
        assert!(
            (nf.c1.im / (2.0 * c.1) - 1.0).abs() < 1e-13 || c.1 == 0.0 && nf.c1.im.abs() < 1e-14
        );
    }
}

#[test]
fn onset_amplitude_is_coordinate_free() {
    // Cycle |Z|^2 = -beta / Re c. Observable y0 = a Re Z + b Im Z has
    // peak-to-peak 2 |a - i b| |Z|; frequency w - Im(c) beta / Re(c).
    let (w, c) = (1.7, (-0.6, 0.9));
    for t in [
        [[1.0, 0.0], [0.0, 1.0]],
        [[2.0, 1.0], [0.0, 1.0]],
        [[0.3, -4.0], [1.0, 2.0]],
    ] {
        let sys = StuartLandau { w, c, t };
        let nf = hopf_normal_form(&sys, &[0.0, 0.0], &[0.0], w).unwrap();
        let dl = eigenvalue_derivative(&sys, &[0.0, 0.0], &[0.0], 0, &nf).unwrap();
        assert!(
            (dl.re - 1.0).abs() < 1e-13 && dl.im.abs() < 1e-13,
            "lambda' = {dl}"
        );
        let law = onset_law(&nf, dl, 0);
        let expect = 2.0 * (t[0][0] * t[0][0] + t[0][1] * t[0][1]).sqrt() / (-c.0).sqrt();
        assert!(
            (law.coefficient / expect - 1.0).abs() < 1e-13,
            "T = {t:?}: {} vs {expect}",
            law.coefficient
        );
        assert_eq!(
            law.side, 1.0,
            "supercritical: the cycle exists for beta > 0"
        );
        assert!((law.frequency_slope + c.1 / c.0).abs() < 1e-13);
    }
}

#[test]
fn subcritical_cycle_lies_on_the_stable_side() {
    let sys = StuartLandau {
        w: 1.0,
        c: (0.5, 0.0),
        t: [[1.0, 0.0], [0.0, 1.0]],
    };
    let nf = hopf_normal_form(&sys, &[0.0, 0.0], &[0.0], 1.0).unwrap();
    let dl = eigenvalue_derivative(&sys, &[0.0, 0.0], &[0.0], 0, &nf).unwrap();
    assert!(nf.l1 > 0.0);
    assert_eq!(onset_law(&nf, dl, 0).side, -1.0);
}
