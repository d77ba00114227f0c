//! Arbitrary input to the scene parser and to `--set` never panics: it is
//! accepted (and then valid) or refused with a message.

use stickslip::scene;

/// SplitMix64, seeded: reproducible pseudo-random input.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[(self.next() % items.len() as u64) as usize]
    }
}

const KEYS: [&str; 18] = [
    "A",
    "B",
    "mu0",
    "mu2",
    "tau",
    "D0",
    "V0",
    "M",
    "W",
    "g",
    "K",
    "V",
    "V_range",
    "name",
    "description",
    "a",
    "V_rnage",
    "",
];
const VALUES: [&str; 22] = [
    "0.012",
    "-1",
    "0",
    "1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "\"text\"",
    "[1, 2]",
    "[2, 1]",
    "[0, 1]",
    "[1]",
    "true",
    "1e-3",
    "3",
    "-0.0",
    "[\"a\", 1]",
    "{ x = 1 }",
    "1_000",
    "0x10",
    "'",
];

#[test]
fn random_scene_files_parse_or_fail_cleanly() {
    let mut rng = Rng(42);
    let mut accepted = 0;
    for _ in 0..3000 {
        let mut text = String::new();
        let n = 1 + rng.next() % 8;
        for _ in 0..n {
            text.push_str(&format!("{} = {}\n", rng.pick(&KEYS), rng.pick(&VALUES)));
        }
        if rng.next().is_multiple_of(5) {
            let cut = (rng.next() as usize) % (text.len() + 1);
            text.truncate(cut);
        }
        match scene::from_toml_str(&text, "fuzz.toml") {
            Ok(s) => {
                accepted += 1;
                s.params.validate().expect("an accepted scene is valid");
                assert!(s.params.to_vec().iter().all(|v| v.is_finite()));
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
    assert!(accepted > 0, "some random scenes should be valid");
}

#[test]
fn random_overrides_are_applied_or_refused_cleanly() {
    let names = [
        "kappa", "nu", "m", "A", "B", "mu0", "mu2", "theta_c", "kapa", "", "nu=", "=1",
    ];
    let values = [
        "1", "-1", "0", "nan", "1e400", "abc", "", "0.5", "1e-300", "=", " 2 ",
    ];
    let mut rng = Rng(7);
    for _ in 0..3000 {
        let mut p = scene::builtin("pmma").unwrap().params;
        let sets: Vec<String> = (0..1 + rng.next() % 4)
            .map(|_| format!("{}={}", rng.pick(&names), rng.pick(&values)))
            .collect();
        match p.apply_overrides(&sets) {
            Ok(()) => p
                .validate()
                .expect("accepted overrides leave valid parameters"),
            Err(e) => assert!(!e.to_string().is_empty(), "{sets:?}"),
        }
    }
}
