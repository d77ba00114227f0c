//! The keys of the two families of friction laws (`law = "rate-and-state"`,
//! `law = "adhesive"`) on the command line and in scene files:
//!
//! - `--set V_range=LO:HI` on an adhesive scene is the scene file's
//!   `V_range = [LO, HI]` (the diagram's velocities equal those of the same
//!   scene written with that key), refused with the rate-and-state
//!   scenes' own messages, naming `--set V_range`;
//! - a refused `--set` value of an adhesive scene names `--set KEY`;
//! - a key of the other family (`A` on an adhesive scene, `F_a` on a
//!   rate-and-state one), given by `--set` or in a scene file, is named as
//!   that family's key, with this scene's law and its keys, never with an
//!   edit-distance guess (`A` is not a misspelt `M`).

mod common;

use common::{json_of, stickslip, temp_dir};

/// The `V_um_per_s` of every point of an adhesive `diagram --json`.
fn diagram_velocities(args: &[&str], out: &str) -> Vec<f64> {
    let (status, v, err) =
        json_of(&[&["diagram", "--json", "--force", "--out", out], args].concat());
    assert_eq!(status, 0, "{args:?}: {err}");
    v["points"]
        .as_array()
        .expect("points")
        .iter()
        .map(|p| p["V_um_per_s"].as_f64().expect("V_um_per_s"))
        .collect()
}

#[test]
fn an_adhesive_scene_takes_v_range_from_set_as_from_its_file() {
    let dir = temp_dir("family-keys-v-range");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let gel = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/gel.toml"
    ))
    .unwrap();
    let text = gel.replace("V_range = [0.1, 1000.0]", "V_range = [1.0, 100.0]");
    assert_ne!(text, gel, "the built-in gel's V_range line");
    let path = dir.join("gel.toml");
    std::fs::write(&path, text).unwrap();

    let by_set = diagram_velocities(&["--scene", "gel", "--set", "V_range=1:100"], out);
    let by_file = diagram_velocities(&["--scene", path.to_str().unwrap()], out);
    assert_eq!(by_set, by_file);
    // 20 points per decade over two decades, from 1 to 100 µm/s.
    assert_eq!(by_set.len(), 41, "{by_set:?}");
    assert!((by_set[0] - 1.0).abs() < 1e-12 && (by_set[40] - 100.0).abs() < 1e-10);

    // Refused as on a rate-and-state scene, word for word.
    for bad in [
        "V_range=10:1",
        "V_range=abc",
        "V_range=0:1",
        "V_range=1:inf",
    ] {
        let (status, _, gel_err) = stickslip(&["hopf", "--scene", "gel", "--set", bad]);
        assert_eq!(status, 2, "{bad}: {gel_err}");
        assert!(gel_err.contains("--set V_range"), "{bad}: {gel_err}");
        let (status, _, pmma_err) = stickslip(&["hopf", "--scene", "pmma", "--set", bad]);
        assert_eq!(status, 2, "{bad}: {pmma_err}");
        assert_eq!(gel_err, pmma_err, "{bad}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_refused_set_value_of_an_adhesive_scene_names_set_and_the_key() {
    for (set, field) in [
        ("K=-1", "--set K = -1"),
        ("alpha=1.5", "--set alpha = 1.5"),
        ("tau_on=0", "--set tau_on = 0"),
        (
            "K=abc",
            "--set K: cannot read 'abc': expected a number in N/m",
        ),
    ] {
        let (status, _, err) = stickslip(&["hopf", "--scene", "gel", "--set", set]);
        assert_eq!(status, 2, "{set}: {err}");
        assert!(err.contains(field), "{set}: {err}");
    }
}

#[test]
fn a_key_of_the_other_law_is_named_as_such() {
    let dir = temp_dir("family-keys-other-law");
    // --set, adhesive scene: rate-and-state keys and dimensionless parameters.
    for key in ["A", "B", "D0", "mu0", "mu2", "W", "tau", "eta", "theta_c"] {
        let set = format!("{key}=0.01");
        let (status, _, err) = stickslip(&["hopf", "--scene", "gel", "--set", &set]);
        assert_eq!(status, 2, "{key}: {err}");
        assert!(
            err.contains(&format!("--set {key}: `{key}` is a rate-and-state key"))
                && err.contains("this scene's law is `adhesive`, whose --set keys are F_a, V_s"),
            "{key}: {err}"
        );
        assert!(!err.contains("did you mean"), "{key}: {err}");
    }
    // --set, rate-and-state scene: adhesive keys.
    for key in ["F_a", "V_s", "tau_out", "tau_on", "F_v", "alpha"] {
        let set = format!("{key}=0.01");
        let (status, _, err) = stickslip(&["hopf", "--scene", "pmma", "--set", &set]);
        assert_eq!(status, 2, "{key}: {err}");
        assert!(
            err.contains(&format!("--set {key}: `{key}` is an adhesive key"))
                && err.contains("this scene's law is `rate-and-state`, whose --set keys are"),
            "{key}: {err}"
        );
        assert!(!err.contains("did you mean"), "{key}: {err}");
    }
    // Scene files, both directions.
    let adhesive = "law = \"adhesive\"\nF_a = 0.05\nV_s = 0.025\ntau_out = 1.0\n\
                    tau_on = 0.1\nV = 20.0\nA = 0.01\n";
    let path = dir.join("gel-with-a.toml");
    std::fs::write(&path, adhesive).unwrap();
    let (status, _, err) = stickslip(&["hopf", "--scene", path.to_str().unwrap()]);
    assert_eq!(status, 2, "{err}");
    assert!(
        err.contains("gel-with-a.toml: key A: `A` is a rate-and-state key")
            && err.contains("this scene's law is `adhesive`, whose keys are law, name"),
        "{err}"
    );
    assert!(!err.contains("did you mean"), "{err}");
    let pmma = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/pmma.toml"
    ))
    .unwrap();
    let path = dir.join("pmma-with-fv.toml");
    std::fs::write(&path, format!("{pmma}\nF_v = 1e-3\n")).unwrap();
    let (status, _, err) = stickslip(&["hopf", "--scene", path.to_str().unwrap()]);
    assert_eq!(status, 2, "{err}");
    assert!(
        err.contains("pmma-with-fv.toml: key F_v: `F_v` is an adhesive key")
            && err.contains("this scene's law is `rate-and-state`, whose keys are law, name"),
        "{err}"
    );
    assert!(!err.contains("did you mean"), "{err}");
    // A misspelling of this law's key still gets its suggestion.
    let (status, _, err) = stickslip(&["hopf", "--scene", "gel", "--set", "Fa=0.1"]);
    assert_eq!(status, 2, "{err}");
    assert!(err.contains("did you mean 'F_a'"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
