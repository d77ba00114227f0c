use stickslip::analysis::cycle_at::cycle_at;
use stickslip::analysis::cycles::CycleRequest;
use stickslip::analysis::orbit_inertia::InertiaWatch;
use stickslip::jobs::SceneSpec;
fn main() {
    let v: f64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let ntst: usize = std::env::args().nth(2).map_or(40, |s| s.parse().unwrap());
    let mut spec = SceneSpec::named("examples/scenes/rig.toml");
    spec.set = vec![format!("V={v}")];
    let setup = spec.setup(|p| *p).unwrap();
    let t = std::time::Instant::now();
    let watch = InertiaWatch::new(&setup.scene_params, 1e-3, true);
    let req = CycleRequest {
        kappa_min: 0.0,
        kappa_max: f64::INFINITY,
        max_steps: 500,
        ntst,
        at_kappa: vec![],
        ntst_max: 12800,
        collocation: None,
    };
    let r = cycle_at(
        &setup.scene_params,
        setup.choice.kind,
        setup.scene_params.kappa,
        &watch,
        &req,
    );
    match r {
        Ok(c) => {
            let r = c.record;
            let u = setup.scene.units;
            println!("{:?} periods {} period {:.10e} s  dS {:.10e} N  v {:.3e}..{:.3e} ntst {} err {:?} stab {:?} t {:?}", c.simulated.kind, c.simulated.orbit.periods, r.period*u.d0/u.v0, r.delta_s*300.0, r.v_min, r.v_max, r.ntst, r.error_estimate, r.stability, t.elapsed());
        }
        Err(e) => println!("ERR {e} {:?}", t.elapsed()),
    }
}
