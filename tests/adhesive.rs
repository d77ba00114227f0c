//! Issue 27, soft adhesive contacts (Schallamach; seed §III.D.3, Appendix D):
//!
//! - `E1` and `g(z) = e^z E1(z)` with their derivatives of orders 1–5 on
//!   the engine's dual numbers, against 40-digit mpmath values over
//!   `1e-8 <= z <= 1e3` (docs/reference/exp_integral.py,
//!   exp_integral_out.txt);
//! - the steady state (D2) and the limits (D8)–(D11), against the seed's
//!   asymptotic forms with their next-order bounds;
//! - the gel scene's `V_max`, `V_c`, `kappa_c`, `Omega_c` against mpmath
//!   (docs/reference/adhesive_gel.py, adhesive_gel_out.txt), the onset
//!   located by the engine through `hopf --json`;
//! - every command on a scene written from scratch, its cycle at the
//!   scene's stiffness by collocation against the settled simulation, the
//!   static peak after a stop, and the input errors naming the key.

mod common;

use common::{json_of, stickslip, temp_dir};
use num_dual::{Dual, Dual64, HyperHyperDual64};
use stickslip::adhesive::block::{bond_rate, lifetime, steady_bonds, steady_friction};
use stickslip::adhesive::params::AdhesiveParams;
use stickslip::exp_integral::{e1, scaled_e1};

/// The rows of a reference file: `key value` lines under `[section]`.
fn reference(section: &str) -> std::collections::HashMap<String, f64> {
    let text = include_str!("../docs/reference/adhesive_gel_out.txt");
    let mut inside = false;
    let mut out = std::collections::HashMap::new();
    for line in text.lines() {
        if line.starts_with('[') {
            inside = line == format!("[{section}]");
        } else if let (true, Some((k, v))) = (inside, line.split_once(' ')) {
            out.insert(k.to_string(), v.parse().unwrap());
        }
    }
    out
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// The `k`-th derivative of `g` at `z` on the dual types the engine uses
/// for each order: `Dual64`, nested duals, `HyperHyperDual64`, and duals of
/// it (orders 4, 5).
fn g_derivative(k: usize, z: f64) -> f64 {
    type D2 = Dual<Dual64>;
    type D4 = Dual<HyperHyperDual64>;
    type D5 = Dual<D4>;
    match k {
        0 => scaled_e1(z),
        1 => scaled_e1(Dual64::new(z, 1.0)).eps,
        2 => {
            scaled_e1(D2::new(Dual64::new(z, 1.0), Dual64::from(1.0)))
                .eps
                .eps
        }
        3 => scaled_e1(HyperHyperDual64::new(z, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0)).eps1eps2eps3,
        4 => {
            let h = HyperHyperDual64::new(z, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
            scaled_e1(D4::new(h, HyperHyperDual64::from(1.0)))
                .eps
                .eps1eps2eps3
        }
        _ => {
            let h = HyperHyperDual64::new(z, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
            let d4 = D4::new(h, HyperHyperDual64::from(1.0));
            scaled_e1(D5::new(d4, D4::from(1.0))).eps.eps.eps1eps2eps3
        }
    }
}

#[test]
fn g_and_its_derivatives_of_orders_1_to_5_match_mpmath_from_1e_minus_8_to_1e3() {
    let text = include_str!("../docs/reference/exp_integral_out.txt");
    let (mut worst, mut rows) = (0.0f64, 0);
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let cols: Vec<f64> = line.split(' ').map(|c| c.parse().unwrap()).collect();
        let z = cols[0];
        assert!((1e-8..=1e3).contains(&z), "z = {z}");
        for k in 0..=5 {
            let err = rel(g_derivative(k, z), cols[1 + k]);
            worst = worst.max(err);
            assert!(
                err < 1e-13,
                "g^({k})({z}): {} vs {}",
                g_derivative(k, z),
                cols[1 + k]
            );
        }
        if z <= 700.0 {
            assert!(
                rel(e1(z), cols[7]) < 1e-13,
                "E1({z}) = {} vs {}",
                e1(z),
                cols[7]
            );
        }
        rows += 1;
    }
    assert!(rows >= 35, "{rows} rows");
    eprintln!("worst relative error over g^(0..5): {worst:.2e}");
}

fn schallamach(r: f64) -> AdhesiveParams {
    AdhesiveParams {
        kappa: 0.0,
        nu: 1.0,
        r,
        f_v: 0.0,
        alpha: 0.0,
        m: 0.0,
    }
}

#[test]
fn steady_bonds_are_d2_and_the_kinetics_vanish_there() {
    for (u, r) in [(1e-3, 0.1), (1.0, 0.5), (40.0, 0.1), (1e5, 0.9)] {
        let t = lifetime(u);
        let n = steady_bonds(u, r);
        assert!(rel(n, t / (t + r)) < 1e-15, "D2 at u = {u}");
        // dn/dt = (1 - n)/r - n/T vanishes up to the rounding of its terms.
        let scale = (1.0 - n) / r;
        assert!(
            bond_rate(u, n, r).abs() < 4.0 * f64::EPSILON * scale,
            "u = {u}"
        );
    }
}

#[test]
fn the_limits_d8_to_d11_hold_with_their_next_order() {
    let euler = 0.577_215_664_901_532_9;
    // D8: t / tau_out = 1 - V/V_s + ... (next term 2 (V/V_s)^2).
    for u in [1e-6f64, 1e-4, 1e-3] {
        assert!(
            ((lifetime(u) - 1.0) / u + 1.0).abs() < 3.0 * u,
            "D8 at u = {u}"
        );
    }
    // D9: t / tau_out = (V_s/V) (ln(V/V_s) - 0.577...); e^z E1(z) = -gamma
    // - ln z + z (1 - gamma - ln z) + ..., so the next term is (ln u - gamma + 1)/u^2.
    for u in [1e4f64, 1e6, 1e8] {
        let d9 = (u.ln() - euler) / u;
        assert!(rel(lifetime(u), d9) < 2.0 / u, "D9 at u = {u}");
    }
    // D10: F = N0 kappa tau_out^2 / (tau + tau_out) V, i.e. u / (1 + r).
    let p = schallamach(0.1);
    for u in [1e-6, 1e-4] {
        assert!(
            rel(steady_friction(u, &p), u / 1.1) < 3.0 * u,
            "D10 at u = {u}"
        );
    }
    // D11: F = (tau_out / tau) (V_s/V) ln^2(V/V_s) at V >> V_max, with the
    // constant of D9 kept: (ln u - gamma)^2 / (r u); next order T / r.
    for u in [1e6f64, 1e8] {
        let d11 = (u.ln() - euler).powi(2) / (0.1 * u);
        let bound = 2.0 * (lifetime(u) / 0.1 + 1.0 / u.ln());
        assert!(rel(steady_friction(u, &p), d11) < bound, "D11 at u = {u}");
    }
}

fn field(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn the_gel_scene_has_the_reference_v_max_v_c_and_onset() {
    let r = reference("gel");
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        rel(field(&v, "V_max_um_per_s"), r["V_max_um_s"]) < 1e-9,
        "{v}"
    );
    assert!(rel(field(&v, "V_c_um_per_s"), r["V_c_um_s"]) < 1e-9, "{v}");
    assert!(rel(field(&v, "force_at_V_max_N"), r["F_max_N"]) < 1e-12);
    assert!(rel(field(&v, "force_at_V_c_N"), r["F_min_N"]) < 1e-12);
    assert!(rel(field(&v, "steady_force_N"), r["steady_force_N"]) < 1e-12);
    // The gel's 1 g block is inertial, judged on its orbit (cycles_judge_
    // the_model_on_the_orbit): K_c with inertia, kappa_c (1 + chi).
    let c = &v["critical"];
    assert_eq!(v["model"], "inertial");
    assert!(
        rel(field(c, "kappa_c"), r["kappa_c_inertial"]) < 1e-9,
        "{c}"
    );
    assert!(
        rel(field(c, "omega_c"), r["omega_c_inertial"]) < 1e-9,
        "{c}"
    );
    assert!(
        rel(field(c, "K_N_per_m"), r["K_c_inertial_N_m"]) < 1e-9,
        "{c}"
    );
    assert!(rel(field(&v, "inertia_ratio"), r["chi"]) < 1e-9, "{v}");
    assert_eq!(c["onset"], "supercritical");
    assert_eq!(v["regime"], "stick-slip");
    // Without inertia, the quasi-static closed form.
    let (status, q, err) = json_of(&[
        "hopf",
        "--scene",
        "gel",
        "--json",
        "--model",
        "quasi-static",
    ]);
    assert_eq!(status, 0, "{err}");
    let c = &q["critical"];
    assert!(rel(field(c, "kappa_c"), r["kappa_c"]) < 1e-9, "{c}");
    assert!(rel(field(c, "omega_c"), r["omega_c"]) < 1e-9, "{c}");
    assert!(rel(field(c, "K_N_per_m"), r["K_c_N_m"]) < 1e-9, "{c}");
    assert_eq!(c["onset"], "supercritical");
    // V_c inside the seed's 25-250 um/s of gelatin.
    assert!((25.0..250.0).contains(&field(&v, "V_c_um_per_s")));
}

const FROM_SCRATCH: &str = "\
law = \"adhesive\"
description = \"a Newtonian junction, written for the test\"
F_a = 0.2
V_s = 0.1
tau_out = 2.0
tau_on = 0.6
F_v = 2e-5
alpha = 0
M = 0.002
K = 1000.0
V = 5.0
V_range = [0.1, 500.0]
";

fn scene_file(dir: &std::path::Path, text: &str) -> String {
    let path = dir.join("soft.toml");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn every_command_runs_on_a_scene_written_from_scratch() {
    let dir = temp_dir("adhesive-scratch");
    let scene = scene_file(&dir, FROM_SCRATCH);
    let out = dir.to_str().unwrap();
    let r = reference("newtonian");
    let (status, v, err) = json_of(&["hopf", "--scene", &scene, "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        rel(field(&v, "V_max_um_per_s"), r["V_max_um_s"]) < 1e-9,
        "{v}"
    );
    assert!(rel(field(&v, "V_c_um_per_s"), r["V_c_um_s"]) < 1e-9, "{v}");
    let (kappa_c, omega_c) = match v["model"].as_str() {
        Some("inertial") => (r["kappa_c_inertial"], r["omega_c_inertial"]),
        _ => (r["kappa_c"], r["omega_c"]),
    };
    assert!(rel(field(&v["critical"], "kappa_c"), kappa_c) < 1e-9);
    assert!(rel(field(&v["critical"], "omega_c"), omega_c) < 1e-9);

    // branch in V: the Hopf points at K = 1000 N/m lie between V_max and V_c.
    let (status, v, err) = json_of(&["branch", "--scene", &scene, "--param", "V", "--json"]);
    assert_eq!(status, 0, "{err}");
    let hopf: Vec<f64> = v["hopf_points_V_um_per_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(hopf.len(), 2, "{v}");
    assert!(
        r["V_max_um_s"] < hopf[0] && hopf[1] < r["V_c_um_s"],
        "{hopf:?}"
    );

    let (status, v, err) = json_of(&["diagram", "--scene", &scene, "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    for p in v["points"].as_array().unwrap() {
        let v_um = field(p, "nu") * 0.1;
        let weakening = r["V_max_um_s"] < v_um && v_um < r["V_c_um_s"];
        assert_eq!(p["kappa_c"].is_number(), weakening, "{p}");
    }

    // cycles: the cycle at the scene's K by collocation against simulation.
    let (status, v, err) = json_of(&["cycles", "--scene", &scene, "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    let c = &v["at_scene"];
    let s = &v["simulated"];
    assert!(rel(field(c, "kappa"), field(&v["params"], "kappa")) < 1e-9);
    assert!(
        rel(field(c, "period"), field(s, "period")) < 1e-5,
        "{c} {s}"
    );
    let drop = field(c, "s_max") - field(c, "s_min");
    assert!(rel(drop, field(s, "force_drop")) < 1e-5, "{c} {s}");

    let (status, v, err) = json_of(&["simulate", "--scene", &scene, "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    assert!(field(&v, "settled_period_s") > 0.0);
    for suffix in [
        "diagram-stability",
        "diagram-steady-friction",
        "cycles-period",
        "cycles-orbits",
    ] {
        assert!(dir.join(format!("soft-{suffix}.png")).is_file(), "{suffix}");
    }
}

#[test]
fn a_stop_longer_than_resticking_gives_a_static_peak_a_short_one_none() {
    let dir = temp_dir("adhesive-stop");
    let out = dir.to_str().unwrap();
    let peak = |stop: &str, name: &str| {
        let protocol = format!("200:20,0:{stop},200:10");
        let args = [
            "simulate", "--scene", "gel", "--json", "--out", out, "--name", name,
        ];
        let (status, v, err) = json_of(&[&args[..], &["--protocol", &protocol]].concat());
        assert_eq!(status, 0, "{err}");
        let peaks = v["peak_force_N"].as_array().unwrap().clone();
        (
            peaks[2].as_f64().unwrap(),
            v["steady_force_N"][2].as_f64().unwrap(),
        )
    };
    let (short, steady) = peak("0.02", "short");
    let (long, _) = peak("1", "long");
    // Above V_c steady sliding is stable: without a stop no peak, after a
    // stop of tau_on's order none either, after a full resticking one.
    assert!(short < 1.01 * steady, "{short} vs {steady}");
    assert!(long > 3.0 * steady, "{long} vs {steady}");
}

#[test]
fn bad_adhesive_input_names_the_key() {
    let dir = temp_dir("adhesive-errors");
    for (change, key) in [
        ("tau_on = -0.6", "tau_on"),
        ("alpha = 1.0", "alpha"),
        ("F_v = -1e-5", "F_v"),
        ("F_a = 0", "F_a"),
        ("V_s = nan", "V_s"),
        ("K = -1", "K"),
        ("tau_out = 'long'", "tau_out"),
        ("tau_onn = 1", "tau_onn"),
        ("law = \"glue\"", "law"),
    ] {
        let first = change.split(' ').next().unwrap();
        let text: String = FROM_SCRATCH
            .lines()
            .filter(|l| !l.starts_with(&format!("{first} ")))
            .chain([change])
            .collect::<Vec<_>>()
            .join("\n");
        let scene = scene_file(&dir, &text);
        let (status, _, err) = stickslip(&["hopf", "--scene", &scene]);
        assert_eq!(status, 2, "{change}: {err}");
        assert!(err.contains(key), "{change}: {err}");
    }
    // A heavy block is no longer refused: the inertial model, saying why.
    let scene = scene_file(&dir, &FROM_SCRATCH.replace("M = 0.002", "M = 50"));
    let (status, v, err) = json_of(&["hopf", "--scene", &scene, "--json"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "inertial", "{v}");
    assert!(
        v["model_reason"].as_str().unwrap().contains("M = 5e1 kg"),
        "{v}"
    );
    let data = dir.join("steady.csv");
    std::fs::write(&data, "V,mu\n1,0.5\n").unwrap();
    let data = format!("steady={}", data.display());
    for args in [
        vec!["hopf", "--scene", "gel", "--set", "kappa=0.1"],
        vec!["cycles", "--scene", "gel", "--param", "V"],
        vec!["fit", "--scene", "gel", "--data", &data],
    ] {
        let (status, _, err) = stickslip(&args);
        assert_eq!(status, 2, "{args:?}: {err}");
        assert!(err.contains("adhesive"), "{args:?}: {err}");
    }
}

/// `--set` on an adhesive scene gives its numbers in the scene file's
/// units: `K = 1e5 N/m` is `kappa = K V_s tau_out / F_a = 0.05`, above the
/// gel's `K_c = 7.378e4 N/m` (steady sliding), `K = 5e4 N/m` below it
/// (stick-slip); a set value is checked as the file's own.
#[test]
fn set_overrides_the_adhesive_scenes_numbers() {
    let run = |k: &str| {
        let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--json", "--set", k]);
        assert_eq!(status, 0, "{err}");
        v
    };
    let stiff = run("K=1e5");
    assert!(rel(field(&stiff["params"], "kappa"), 0.05) < 1e-14);
    assert_eq!(stiff["regime"], "steady sliding");
    assert_ne!(run("K=5e4")["regime"], "steady sliding");
    for (set, words) in [
        ("K=-1", "K = -1"),
        ("Kx=1", "did you mean 'K'"),
        ("alpha=1", "alpha"),
        ("tau_on", "KEY=VALUE"),
    ] {
        let (status, _, err) = stickslip(&["hopf", "--scene", "gel", "--set", set]);
        assert_eq!(status, 2, "{set}: {err}");
        assert!(err.contains(words), "{set}: {err}");
    }
}

/// The gel with the mass `m` (dimensionless) at its velocity.
fn gel_with_mass(m: f64) -> AdhesiveParams {
    let mut p = stickslip::adhesive::scene::load("gel").unwrap().params;
    p.m = m;
    p
}

/// The inertial block's critical stiffness located by the engine (the
/// steady branch continued in kappa, Newton on the Hopf system) against
/// the closed form `kappa_c = -lambda_n dF_ss/du (1 + chi)` of the cubic
/// characteristic polynomial, over five decades of chi; and the limit
/// `m -> 0`: the quasi-static closed form, approached as `1 + chi`.
#[test]
fn the_inertial_onset_is_the_closed_form_and_tends_to_the_quasi_static_one() {
    use stickslip::adhesive::analysis::onset::{find_onset, OnsetOutcome};
    use stickslip::adhesive::block::{
        critical_stiffness, critical_stiffness_of, inertia_ratio, InertialAdhesiveBlock,
    };
    use stickslip::model::ModelKind;
    let onset = |p: &AdhesiveParams| match find_onset(InertialAdhesiveBlock, p).unwrap() {
        OnsetOutcome::Found(o) => o,
        other => panic!("{other:?}"),
    };
    for m in [1e-12, 1e-10, 5e-10, 1e-8, 1e-6, 1e-5] {
        let p = gel_with_mass(m);
        let o = onset(&p);
        let (closed, omega) = critical_stiffness_of(&p, ModelKind::Inertial);
        assert!(
            rel(o.kappa_c, closed) < 1e-10,
            "m = {m}: {} vs {closed}",
            o.kappa_c
        );
        assert!(
            rel(o.omega_c, omega) < 1e-9,
            "m = {m}: {} vs {omega}",
            o.omega_c
        );
        assert!(o.l1.is_finite() && o.state.len() == 3);
    }
    let (quasi, _) = critical_stiffness(&gel_with_mass(0.0));
    let mut last = f64::INFINITY;
    for m in [1e-9, 1e-11, 1e-13, 1e-15] {
        let p = gel_with_mass(m);
        let gap = rel(onset(&p).kappa_c, quasi);
        let chi = inertia_ratio(&p);
        assert!(
            (gap - chi).abs() < 1e-9 + 1e-6 * chi,
            "m = {m}: {gap} vs chi {chi}"
        );
        assert!(gap < last);
        last = gap;
    }
    assert!(last < 1e-9, "{last}");
}

/// `hopf` on the gel at V = 50 um/s (chi = 2.5e-3 above the threshold
/// 1e-3) runs the inertial model and says why; at 20 um/s (chi = 4.4e-4)
/// too, by its orbit (as `cycles`), and with a 1 µg block the quasi-static
/// one; `--model` forces either.
#[test]
fn hopf_chooses_the_inertial_model_where_chi_exceeds_the_threshold() {
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--set", "V=50", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "inertial");
    let why = v["model_reason"].as_str().unwrap();
    assert!(why.contains("is not below the inertia threshold"), "{why}");
    assert!(rel(field(&v, "inertia_ratio"), 2.508e-3) < 1e-3, "{v}");
    let c = &v["critical"];
    assert!(
        rel(field(c, "kappa_c"), field(c, "kappa_c_closed_form")) < 1e-10,
        "{c}"
    );
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "inertial");
    let why = v["model_reason"].as_str().unwrap();
    assert!(
        why.contains("on the quasi-static orbit at K = 2.000000e2 N/m"),
        "{why}"
    );
    let (status, light, err) = json_of(&["hopf", "--scene", "gel", "--set", "M=1e-9", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(light["model"], "quasi-static");
    let (status, v, err) = json_of(&[
        "hopf",
        "--scene",
        "gel",
        "--json",
        "--model",
        "quasi-static",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "quasi-static");
    let (status, f, err) = json_of(&["hopf", "--scene", "gel", "--json", "--model", "inertial"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(f["model"], "inertial");
    assert!(f["model_reason"].as_str().unwrap().starts_with("forced"));
    // Forcing inertia on a block without mass is refused, naming M.
    let (status, _, err) = stickslip(&[
        "hopf", "--scene", "gel", "--set", "M=0", "--model", "inertial",
    ]);
    assert!(status == 2 && err.contains("M [kg] > 0"), "{err}");
    // simulate judges every pulling velocity of its protocol: 200 um/s
    // (chi = 2.5e-2) asks for inertia though the scene's 20 um/s does not.
    let dir = temp_dir("adhesive-protocol-model");
    let out = dir.to_str().unwrap();
    let (status, s, err) = json_of(&[
        "simulate",
        "--scene",
        "gel",
        "--json",
        "--out",
        out,
        "--protocol",
        "20:5,200:5",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(s["model"], "inertial");
    assert!(s["model_reason"]
        .as_str()
        .unwrap()
        .contains("V = 2.000000e2 µm/s"));
    // Inertia raises kappa_c by 1 + chi.
    let ratio = field(&f["critical"], "kappa_c") / field(&v["critical"], "kappa_c");
    assert!(
        rel(ratio - 1.0, field(&v, "inertia_ratio")) < 1e-8,
        "{ratio}"
    );
}

/// `diagram` on the gel sweeps 0.1-1000 um/s, where chi crosses the
/// threshold: the inertial model over the range, and each point's verdict
/// is `hopf`'s at that velocity, its K_c `hopf`'s (exactly where `hopf` is
/// inertial, within chi where it is quasi-static).
#[test]
fn diagram_judges_chi_over_its_range_as_hopf_does_at_each_velocity() {
    let dir = temp_dir("adhesive-diagram-model");
    let out = dir.to_str().unwrap();
    let (status, d, err) = json_of(&["diagram", "--scene", "gel", "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(d["model"], "inertial", "{}", d["model_reason"]);
    let crossing = field(&d, "inertia_crossing_um_per_s");
    assert!(d["model_reason"].as_str().unwrap().contains("crosses"));
    let points = d["points"].as_array().unwrap();
    let v_s = 0.025;
    // The physical values beside the dimensionless ones: V = nu V_s, K_c =
    // kappa_c F_a / (V_s tau_out) = kappa_c 2e6 N/m, f = omega / (2 pi
    // tau_out), steady force = s F_a (the gel's 0.05 N, 0.025 µm/s, 1 s).
    for p in points {
        assert!((field(p, "V_um_per_s") / (field(p, "nu") * v_s) - 1.0).abs() < 1e-14);
        if p["kappa_c"].is_number() {
            let k = field(p, "kappa_c") * 2e6;
            assert!((field(p, "K_N_per_m") / k - 1.0).abs() < 1e-14, "{p}");
            let f = field(p, "omega_c") / (2.0 * std::f64::consts::PI);
            assert!((field(p, "frequency_hz") / f - 1.0).abs() < 1e-14, "{p}");
        } else {
            assert!(
                p["K_N_per_m"].is_null() && p["frequency_hz"].is_null(),
                "{p}"
            );
        }
    }
    for p in d["steady"].as_array().unwrap() {
        let f = field(p, "s") * 0.05;
        assert!((field(p, "steady_force_N") / f - 1.0).abs() < 1e-14, "{p}");
        assert!((field(p, "V_um_per_s") / (field(p, "nu") * v_s) - 1.0).abs() < 1e-14);
    }
    let mut checked = 0;
    for p in points.iter().step_by(4) {
        let v = field(p, "nu") * v_s;
        let set = format!("V={v}");
        let (status, h, err) = json_of(&["hopf", "--scene", "gel", "--set", &set, "--json"]);
        assert_eq!(status, 0, "{err}");
        let needs = p["needs_inertia"].as_bool().unwrap();
        assert_eq!(needs, at_v_alone(&h), "V = {v}: {p} {}", h["model_reason"]);
        assert_eq!(
            needs,
            v > crossing,
            "V = {v} against the crossing {crossing}"
        );
        if let Some(k) = p["kappa_c"].as_f64() {
            let kh = field(&h["critical"], "kappa_c");
            let chi = field(&h, "inertia_ratio");
            let tol = if h["model"] == "inertial" {
                1e-9
            } else {
                1.01 * chi
            };
            assert!(rel(k, kh) < tol, "V = {v}: {k} vs {kh}");
            checked += 1;
        }
    }
    assert!(checked >= 3, "{checked}");
    // Either side of the crossing, hopf decides accordingly.
    for (v, model) in [
        (0.999 * crossing, "quasi-static"),
        (1.001 * crossing, "inertial"),
    ] {
        let set = format!("V={v}");
        let (_, h, _) = json_of(&["hopf", "--scene", "gel", "--set", &set, "--json"]);
        assert_eq!(at_v_alone(&h), model == "inertial", "V = {v}");
    }
}

/// Whether `hopf` (its JSON `h`) takes the inertial model by `chi` or
/// the onset type at the scene's velocity alone, before judging the
/// scene's orbit (a diagram point's `needs_inertia`).
fn at_v_alone(h: &serde_json::Value) -> bool {
    let why = h["model_reason"].as_str().unwrap_or_default();
    h["model"] == "inertial" && !why.starts_with("inertial: on the quasi-static orbit")
}

/// The inertial gel's stick-slip at its K = 200 N/m (V = 50 um/s): the
/// cycle by collocation of the implicit form against `simulate`'s settled
/// orbit (Radau IIA in time), period and force drop to 1e-6.
#[test]
fn the_inertial_cycle_at_the_gels_stiffness_is_simulates_settled_orbit() {
    let dir = temp_dir("adhesive-inertial-cycle");
    let out = dir.to_str().unwrap();
    let args = ["--scene", "gel", "--set", "V=50", "--json", "--out", out];
    let (status, c, err) = json_of(&[&["cycles"][..], &args].concat());
    assert_eq!(status, 0, "{err}");
    assert_eq!(c["model"], "inertial");
    let (status, s, err) = json_of(&[&["simulate"][..], &args].concat());
    assert_eq!(status, 0, "{err}");
    assert_eq!(s["model"], "inertial");
    let cycle = &c["at_scene"];
    let (f_a, tau_out) = (0.05, 1.0);
    let period = field(cycle, "period") * tau_out;
    let drop = (field(cycle, "s_max") - field(cycle, "s_min")) * f_a;
    assert!(
        rel(period, field(&s, "settled_period_s")) < 1e-6,
        "{cycle} {s}"
    );
    assert!(
        rel(drop, field(&s, "settled_force_drop_N")) < 1e-6,
        "{cycle} {s}"
    );
    assert!(cycle["stable"].as_bool().unwrap());
}

/// The first Lyapunov coefficient of the inertial block, from the engine's
/// normal form in `(s, ln u, n)`: its coordinate-free consequence, the
/// amplitude coefficient `C` of `Delta_s ~ C sqrt|kappa - kappa_c|`,
/// tends to the quasi-static block's as `m -> 0`, the onset type with it.
#[test]
fn the_inertial_amplitude_coefficient_tends_to_the_quasi_static_one() {
    use stickslip::adhesive::analysis::onset::{find_onset, OnsetOutcome};
    use stickslip::adhesive::block::{AdhesiveBlock, InertialAdhesiveBlock};
    let quasi = match find_onset(AdhesiveBlock, &gel_with_mass(0.0)).unwrap() {
        OnsetOutcome::Found(o) => o,
        other => panic!("{other:?}"),
    };
    let c0 = quasi.amplitude_coefficient.unwrap();
    let mut last = f64::INFINITY;
    for m in [1e-10, 1e-12, 1e-14] {
        let o = match find_onset(InertialAdhesiveBlock, &gel_with_mass(m)).unwrap() {
            OnsetOutcome::Found(o) => o,
            other => panic!("{other:?}"),
        };
        assert_eq!(o.onset.name(), quasi.onset.name());
        let gap = rel(o.amplitude_coefficient.unwrap(), c0);
        assert!(gap < last.min(1e-3), "m = {m}: {gap}");
        last = gap;
    }
    assert!(last < 1e-6, "{last}");
}

/// `branch --param V` on the gel in the inertial model (chosen over the
/// range): its Hopf points are where the inertial closed form's
/// `kappa_c(V)` equals the scene's `kappa`.
#[test]
fn the_inertial_branch_hopf_points_are_where_kappa_c_is_the_scenes() {
    use stickslip::adhesive::block::critical_stiffness_of;
    use stickslip::model::ModelKind;
    let (status, v, err) = json_of(&["branch", "--scene", "gel", "--param", "V", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "inertial");
    let kappa = field(&v["params"], "kappa");
    let points = v["hopf_points"].as_array().unwrap();
    assert_eq!(points.len(), 2, "{v}");
    for h in points {
        let mut p = gel_with_mass(5e-10);
        p.nu = field(h, "nu");
        let (k, _) = critical_stiffness_of(&p, ModelKind::Inertial);
        assert!(rel(k, kappa) < 1e-9, "{h}: {k} vs {kappa}");
    }
}

/// Near the gel's Bautin point (the quasi-static onset changes from
/// subcritical to supercritical at about 0.75 um/s), a small inertia,
/// chi far below the threshold, changes the onset type in a narrow window
/// of velocities: there `hopf` takes the inertial model and says why, as
/// the rate-and-state block does; away from it, the quasi-static one.
#[test]
fn where_inertia_changes_the_onset_type_hopf_takes_the_inertial_model() {
    use stickslip::adhesive::analysis::steady::diagram;
    use stickslip::adhesive::block::{AdhesiveBlock, InertialAdhesiveBlock};
    let p = gel_with_mass(5e-10);
    let l1 = |nu: f64, inertial: bool| {
        let d = if inertial {
            diagram(InertialAdhesiveBlock, &p, &[nu], 1.0)
        } else {
            diagram(AdhesiveBlock, &p, &[nu], 1.0)
        };
        d.unwrap()[0].l1.unwrap()
    };
    // The quasi-static Bautin point by bisection in nu (l1 > 0 below).
    let (mut lo, mut hi) = (0.70 / 0.025, 0.80 / 0.025);
    assert!(l1(lo, false) > 0.0 && l1(hi, false) < 0.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if l1(mid, false) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    // The inertial l1 there has a sign; just on the other side the
    // quasi-static one has the other.
    let inertial_sign = l1(lo, true).signum();
    let nu = if inertial_sign < 0.0 { lo } else { hi };
    assert!(l1(nu, false).signum() != inertial_sign && l1(nu, true).signum() == inertial_sign);
    let set = format!("V={}", nu * 0.025);
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--set", &set, "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(field(&v, "inertia_ratio") < 1e-3);
    assert_eq!(v["model"], "inertial", "{}", v["model_reason"]);
    assert!(v["model_reason"].as_str().unwrap().contains("onset type"));
    let (_, v, _) = json_of(&["hopf", "--scene", "gel", "--set", "V=0.6", "--json"]);
    assert_eq!(v["model"], "quasi-static");
    // diagram over 0.6 - 0.9 um/s with that velocity in its grid: the
    // point there needs inertia, as hopf said, the others not.
    let dir = temp_dir("adhesive-bautin");
    let text = include_str!("../examples/scenes/gel.toml").replace(
        "V_range = [0.1, 1000.0]",
        &format!("V_range = [{}, 0.9]", nu * 0.025),
    );
    let scene = scene_file(&dir, &text);
    let args = [
        "diagram",
        "--scene",
        &scene,
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ];
    let (status, d, err) = json_of(&args);
    assert_eq!(status, 0, "{err}");
    assert_eq!(d["model"], "inertial", "{}", d["model_reason"]);
    let points = d["points"].as_array().unwrap();
    assert_eq!(points[0]["needs_inertia"], true, "{}", points[0]);
    assert!(points[points.len() - 1]["needs_inertia"] == false);
}

/// `K = 0` on an adhesive scene (no spring): `hopf` leaves the regime
/// undecided, as for the rate-and-state block, and `cycles` traces down to
/// half the critical stiffness, one step past it at most (it ran toward
/// `kappa = 0` without end).
#[test]
fn no_spring_is_no_operating_point() {
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--set", "K=0", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        v["regime"]
            .as_str()
            .unwrap()
            .starts_with("undecided: K = 0"),
        "{}",
        v["regime"]
    );
    let dir = temp_dir("adhesive-no-spring");
    let out = dir.to_str().unwrap();
    let args = [
        "cycles", "--scene", "gel", "--set", "K=0", "--json", "--out", out, "--force",
    ];
    let (status, v, err) = json_of(&args);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(status, 0, "{err}");
    let kappa_c = field(&v["onset"], "kappa_c");
    let kappas: Vec<f64> = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| field(c, "kappa"))
        .collect();
    // Down to half of kappa_c, and one step past it at most: only the
    // last cycle lies below it.
    let (last, before) = kappas.split_last().unwrap();
    assert!(*last <= 0.5 * kappa_c, "{kappas:?} against {kappa_c}");
    assert!(
        before.iter().all(|k| *k > 0.5 * kappa_c),
        "{kappas:?} against {kappa_c}"
    );
}

/// Every adhesive command's JSON has the common frame: `complete`, `stop`,
/// and `units` in named physical units (`F_a_N`, `V_s_um_per_s` as the
/// scene file gives it, `tau_out_s`, `M_kg`).
#[test]
fn adhesive_json_has_the_common_frame() {
    let dir = temp_dir("adhesive-frame");
    let out = dir.to_str().unwrap();
    for command in ["hopf", "diagram", "simulate"] {
        let args = ["--scene", "gel", "--json", "--out", out, "--force"];
        let args: Vec<&str> = std::iter::once(command)
            .chain(
                if command == "hopf" {
                    &args[..3]
                } else {
                    &args[..]
                }
                .iter()
                .copied(),
            )
            .collect();
        let (status, v, err) = json_of(&args);
        assert_eq!(status, 0, "{command}: {err}");
        assert_eq!(v["complete"], true, "{command}");
        assert!(v.get("stop").is_some(), "{command}: no stop");
        let u = &v["setup"]["units"];
        let u = if u.is_null() { &v["units"] } else { u };
        assert_eq!(field(u, "V_s_um_per_s"), 0.025, "{command}: {u}");
        assert_eq!(field(u, "F_a_N"), 0.05);
        assert_eq!(field(u, "tau_out_s"), 1.0);
        assert_eq!(field(u, "M_kg"), 1e-3);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `simulate`'s protocol in the JSON in the experimenter's units beside
/// the dimensionless ones: the command line's velocities and durations
/// back, and `nu = V / V_s`, `duration = T / tau_out` (here tau_out = 2 s).
#[test]
fn simulate_protocol_is_given_in_um_per_s_and_seconds_too() {
    let dir = temp_dir("adhesive-protocol-units");
    let (status, v, err) = json_of(&[
        "simulate",
        "--scene",
        "gel",
        "--set",
        "tau_out=2",
        "--protocol",
        "200:4,0:1,50:2",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(status == 0 || status == 4, "{err}");
    let protocol = v["protocol"].as_array().unwrap();
    let given = [(200.0, 4.0), (0.0, 1.0), (50.0, 2.0)];
    assert_eq!(protocol.len(), given.len());
    for (seg, (speed, t)) in protocol.iter().zip(given) {
        assert_eq!(field(seg, "V_um_per_s"), speed, "{seg}");
        assert_eq!(field(seg, "duration_s"), t, "{seg}");
        assert!((field(seg, "nu") - speed / 0.025).abs() <= 1e-12 * speed / 0.025);
        assert!((field(seg, "duration") - t / 2.0).abs() < 1e-15, "{seg}");
    }
}

/// `--set` of a key the adhesive scene does not have: a dimensionless
/// parameter names the scene key it comes from (`nu` is `V`, not the
/// `M` an edit distance would pick), a rate-and-state key gets no
/// suggestion, and every message lists the scene's keys.
#[test]
fn unknown_set_keys_list_the_adhesive_keys() {
    let keys = "F_a, V_s, tau_out, tau_on, F_v, alpha, M, K, V";
    for (key, says) in [
        ("nu", Some("'V'")),
        ("kappa", Some("'K'")),
        ("r", Some("'tau_on'")),
        ("tau_of", Some("'tau_on'")),
        ("mu0", None),
        ("A", None),
    ] {
        let set = format!("{key}=3");
        let (status, _, err) = stickslip(&["hopf", "--scene", "gel", "--set", &set]);
        assert_eq!(status, 2, "{err}");
        assert!(err.contains(keys), "{err}");
        match says {
            Some(s) => assert!(err.contains(&format!("did you mean {s}?")), "{err}"),
            None => assert!(!err.contains("did you mean"), "{err}"),
        }
    }
}

/// `tau_on > tau_out` is valid (the bond kinetics and friction law hold
/// for every r > 0) but outside Schallamach's assumption: accepted with a
/// warning on stderr and in the JSON, the run complete; the gel (r = 0.1)
/// has none.
#[test]
fn slow_readsorption_is_warned_not_refused() {
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--set", "tau_on=2", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        err.contains("warning: tau_on = 2e0 s > tau_out = 1e0 s"),
        "{err}"
    );
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{v}");
    // n = 1 / (1 + r) at rest, r = 2.
    assert!(warnings[0]
        .as_str()
        .unwrap()
        .contains("n = 1/(1 + r) = 0.3333"));
    assert_eq!(v["complete"], true);
    let (status, v, err) = json_of(&["hopf", "--scene", "gel", "--json"]);
    assert_eq!(status, 0, "{err}");
    assert!(v["warnings"].as_array().unwrap().is_empty() && !err.contains("warning"));
}

/// `diagram`'s verdict at the scene's own K and V, judged as the
/// rate-and-state diagram judges it: the gel's 200 N/m at 20 µm/s lies far
/// below K_c (the value of docs/reference/fit_adhesive_data.py, with the
/// block's inertia: the diagram runs inertial), 1e6 N/m above a
/// supercritical onset is steady sliding, and above the subcritical onset
/// at 0.7 µm/s it is undecided (cycles may coexist up to their fold).
#[test]
fn diagram_judges_the_operating_point() {
    let dir = temp_dir("adhesive-operating-point");
    let script = std::fs::read_to_string("docs/reference/fit_adhesive_data_out.txt").unwrap();
    let k_c: f64 = script
        .lines()
        .find(|l| l.starts_with("K_c(20 um/s) with inertia"))
        .and_then(|l| l.rsplit(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    let cases: [(&[&str], &str, &str); 3] = [
        (&[], "stick-slip", "K < K_c"),
        (&["--set", "K=1e6"], "steady", "supercritical"),
        (
            &["--set", "K=1e6", "--set", "V=0.7"],
            "undecided",
            "subcritical",
        ),
    ];
    for (i, (set, regime, says)) in cases.iter().enumerate() {
        let out = dir.join(format!("case-{i}"));
        let args = [
            &[
                "diagram",
                "--scene",
                "gel",
                "--json",
                "--out",
                out.to_str().unwrap(),
            ],
            *set,
        ]
        .concat();
        let (status, v, err) = json_of(&args);
        assert_eq!(status, 0, "{err}");
        let op = &v["operating_point"];
        assert_eq!(op["regime"], *regime, "{op}");
        assert!(op["reason"].as_str().unwrap().contains(says), "{op}");
        assert_eq!(op["in_range"], true);
        if i == 0 {
            let located = field(op, "K_c_N_per_m");
            assert!((located / k_c - 1.0).abs() < 1e-9, "{located} vs {k_c}");
            assert!((field(op, "margin") - (200.0 / k_c - 1.0)).abs() < 1e-9);
        }
    }
    // The text says it too.
    let (status, out, err) = stickslip(&[
        "diagram",
        "--scene",
        "gel",
        "--out",
        dir.join("text").to_str().unwrap(),
    ]);
    assert_eq!(status, 0, "{err}");
    assert!(out.contains("operating point: K = 200.00 N/m"), "{out}");
    assert!(out.contains(": stick-slip — K < K_c"), "{out}");
}

/// `hopf` above a subcritical onset (the gel at 0.7 µm/s, below its Bautin
/// point) does not promise steady sliding alone: cycles may coexist (as
/// `diagram` says; `cycles` locates their fold).
#[test]
fn hopf_above_a_subcritical_onset_says_cycles_may_coexist() {
    let v = common::hopf_json(&["--scene", "gel", "--set", "V=0.7", "--set", "K=1e6"]);
    assert_eq!(v["critical"]["onset"], "subcritical", "{v}");
    let regime = v["regime"].as_str().unwrap();
    assert!(regime.starts_with("undecided"), "{regime}");
    assert!(regime.contains("subcritical onset"), "{regime}");
    assert!(regime.contains("coexist"), "{regime}");
    let v = common::hopf_json(&["--scene", "gel", "--set", "K=1e6"]);
    assert_eq!(v["critical"]["onset"], "supercritical");
    assert_eq!(v["regime"], "steady sliding");
}

/// The regime a simulation settles on is judged against the integration's
/// error: above V_c (96 µm/s for the gel) steady sliding is stable and the
/// run says `steady` (force maxima of rounding size are no stick-slip; a
/// stranger saw "settled stick-slip" with a 1.5e-9 N force drop); at the
/// scene's 20 µm/s it is stick-slip with the force drop `cycles` gives
/// (5.7338e-2 N at K = 200 N/m).
#[test]
fn simulate_tells_steady_sliding_from_stick_slip() {
    let dir = temp_dir("adhesive-regime");
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&[
        "simulate", "--scene", "gel", "--set", "V=200", "--json", "--out", out, "--name", "fast",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["regime"], "steady", "{v}");
    assert!(v["settled"].is_null(), "{v}");
    let (status, v, err) = json_of(&[
        "simulate", "--scene", "gel", "--json", "--out", out, "--name", "slow",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["regime"], "periodic", "{v}");
    let (status, cycles, err) = json_of(&[
        "cycles", "--scene", "gel", "--json", "--out", out, "--name", "cycles",
    ]);
    assert_eq!(status, 0, "{err}");
    let at = &cycles["at_scene"];
    let drop = field(at, "s_max") - field(at, "s_min");
    let drop_n = drop * field(&cycles["units"], "F_a_N");
    assert!(
        rel(field(&v, "settled_force_drop_N"), drop_n) < 1e-6,
        "simulation {} N, collocation {drop_n} N",
        field(&v, "settled_force_drop_N")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The adhesive `cycles --json` speaks the experimenter's units beside the
/// dimensionless values, as its CSV does (a stranger, 2026-11-27: the JSON
/// held `period: 75.76` in units of `tau_out` only). The built-in gel:
/// `F_a = 0.05 N`, `V_s = 0.025 µm/s`, `tau_out = 1 s`, so
/// `K = kappa F_a / (V_s tau_out) = 2e6 kappa N/m`.
#[test]
fn adhesive_cycles_json_carries_the_physical_units() {
    let dir = temp_dir("adhesive_cycle_units");
    let out = dir.to_str().unwrap();
    let (code, v, err) = json_of(&["cycles", "--scene", "gel", "--json", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let (f_a, v_s_um, tau_out) = (0.05, 0.025, 1.0);
    let mut all: Vec<&serde_json::Value> = v["cycles"].as_array().unwrap().iter().collect();
    all.push(&v["at_scene"]);
    for c in all {
        let f = |k: &str| c[k].as_f64().unwrap_or_else(|| panic!("{k} in {c}"));
        let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-14;
        assert!(close(
            f("K_N_per_m"),
            f("kappa") * f_a / (v_s_um * 1e-6 * tau_out)
        ));
        assert!(close(f("period_s"), f("period") * tau_out));
        assert!(close(f("force_drop_N"), (f("s_max") - f("s_min")) * f_a));
        assert!(close(f("s_min_N"), f("s_min") * f_a));
        assert!(close(f("v_max_um_per_s"), f("u_max") * v_s_um));
    }
    // The scene's own K = 200 N/m.
    assert!((v["at_scene"]["K_N_per_m"].as_f64().unwrap() / 200.0 - 1.0).abs() < 1e-12);
}
