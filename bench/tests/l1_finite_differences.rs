//! The first Lyapunov coefficient by finite differences
//! ([`l1_finite_differences`], the method of the work-precision study)
//! against the exact one of the Hopf point.

use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::model::{DrivenBlock, ModelKind};
use stickslip::params::Params;
use stickslip_bench::work_precision::l1_finite_differences;

#[test]
fn l1_agrees_with_finite_differences_to_their_accuracy() {
    let p = Params {
        kappa: 0.0,
        nu: 3.0,
        m: 0.1,
        a: 0.01,
        b: 0.02,
        mu0: 0.6,
        mu2: 5e-4,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let HopfOutcome::Found(h) = find_hopf(ModelKind::Inertial, &p).unwrap() else {
        panic!("no Hopf point: {p:?}");
    };
    let block = DrivenBlock::new(ModelKind::Inertial, &p);
    let mut at = p;
    at.kappa = h.kappa_c;
    let x = [h.state[0], h.state[1], h.state[2]];
    // The FD error falls like h^2 until rounding (eps/h^3) takes over near h ~ 1e-4.
    let errs: Vec<f64> = [1e-2, 3e-3, 1e-3]
        .iter()
        .map(|&step| {
            (l1_finite_differences(&block, &x, &at.to_vec(), h.omega_c, step).unwrap() / h.onset.l1
                - 1.0)
                .abs()
        })
        .collect();
    assert!(
        errs[2] < 1e-4,
        "FD at h = 1e-3 is {:.1e} from the exact l1",
        errs[2]
    );
    assert!(
        errs[0] / errs[2] > 30.0,
        "FD error must shrink like h^2 toward the exact value: {errs:?}"
    );
}
