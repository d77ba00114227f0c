//! Coefficients of the three-stage Radau IIA method (order 5) and of the
//! RADAU5 transformation, error estimate and dense output.
//!
//! The nodes are the zeros of `d^2/ds^2 [s^2 (s - 1)^3]`, i.e.
//! `c1 = (4 - sqrt 6)/10`, `c2 = (4 + sqrt 6)/10`, `c3 = 1`. The inverse of the
//! Butcher matrix `A` has one real eigenvalue `gamma` and a complex pair
//! `alpha +- i beta`; `T` (columns: real eigenvector, real and imaginary part
//! of a complex eigenvector) block-diagonalises it:
//! `T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]`
//! (Hairer & Wanner, *Solving ODEs II*, §IV.8, eq. (8.16)–(8.18)).
//! The numbers are those of Hairer's RADAU5 code (20 digits, more than an
//! `f64` holds), checked by a unit test.

#![allow(clippy::excessive_precision)]

/// First node `c1 = (4 - sqrt 6)/10`.
pub(crate) const C1: f64 = 0.155_051_025_721_682_190_180_271_592_529;
/// Second node `c2 = (4 + sqrt 6)/10`.
pub(crate) const C2: f64 = 0.644_948_974_278_317_809_819_728_407_471;
/// `c1 - 1`.
pub(crate) const C1M1: f64 = C1 - 1.0;
/// `c2 - 1`.
pub(crate) const C2M1: f64 = C2 - 1.0;
/// `c1 - c2`.
pub(crate) const C1MC2: f64 = C1 - C2;

/// Real eigenvalue of `A^-1`.
pub(crate) const GAMMA: f64 = 3.637_834_252_744_495_732_208_418_513_58;
/// Real part of the complex eigenvalues of `A^-1`.
pub(crate) const ALPHA: f64 = 2.681_082_873_627_752_133_895_790_743_21;
/// Imaginary part of the complex eigenvalues of `A^-1`.
pub(crate) const BETA: f64 = 3.050_430_199_247_410_569_426_377_624_79;

/// Coefficients of the embedded error estimate, `e = (gamma0 / h) (dd . Z)`
/// with `gamma0 = 1/GAMMA` (Hairer & Wanner IV.8, eq. (8.20)).
pub(crate) const DD: [f64; 3] = [
    -10.048_809_399_827_415_562_460_329_507_6,
    1.382_142_733_160_748_895_793_662_840_98,
    -1.0 / 3.0,
];

/// `T` (third row `[T31, 1, 0]`).
pub(crate) const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279_2e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];

/// `T^-1`.
pub(crate) const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351_0,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];

#[cfg(test)]
mod tests {
    use super::*;

    fn butcher() -> [[f64; 3]; 3] {
        let s6 = 6f64.sqrt();
        [
            [
                (88.0 - 7.0 * s6) / 360.0,
                (296.0 - 169.0 * s6) / 1800.0,
                (-2.0 + 3.0 * s6) / 225.0,
            ],
            [
                (296.0 + 169.0 * s6) / 1800.0,
                (88.0 + 7.0 * s6) / 360.0,
                (-2.0 - 3.0 * s6) / 225.0,
            ],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ]
    }

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    #[test]
    fn transformation_block_diagonalises_the_inverse_butcher_matrix() {
        let s6 = 6f64.sqrt();
        assert!((C1 - (4.0 - s6) / 10.0).abs() < 1e-16);
        assert!((C2 - (4.0 + s6) / 10.0).abs() < 1e-16);
        let id = mul(&T, &TI);
        // A (T Lambda T^-1) = I is the same as T^-1 A^-1 T = Lambda.
        let lambda = [[GAMMA, 0.0, 0.0], [0.0, ALPHA, -BETA], [0.0, BETA, ALPHA]];
        let a_inv = mul(&mul(&T, &lambda), &TI);
        let should_be_id = mul(&butcher(), &a_inv);
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((id[i][j] - e).abs() < 1e-14, "T T^-1 [{i}][{j}]");
                assert!((should_be_id[i][j] - e).abs() < 1e-13, "A A^-1 [{i}][{j}]");
            }
        }
        // The error-estimate coefficients: dd = -(13 +- 7 sqrt 6)/3, -1/3.
        assert!((DD[0] + (13.0 + 7.0 * s6) / 3.0).abs() < 1e-14);
        assert!((DD[1] - (-13.0 + 7.0 * s6) / 3.0).abs() < 1e-14);
    }
}
