//! LU factorisation with partial pivoting on preallocated storage, for the
//! real `n x n` and complex `n x n` iteration matrices of the Radau step.
//! The buffers are allocated once per integration and refactored in place.

use num_complex::Complex64;
use std::ops::{Div, Mul, Sub};

/// The entries the factorisation works with: `f64` and `Complex64`.
pub(crate) trait Entry:
    Copy + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// A magnitude for pivoting (`|x|` or `|re| + |im|`).
    fn magnitude(self) -> f64;
}

impl Entry for f64 {
    fn magnitude(self) -> f64 {
        self.abs()
    }
}

impl Entry for Complex64 {
    fn magnitude(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
}

/// A dense row-major matrix and its in-place LU factors `P A = L U`.
pub(crate) struct Lu<T> {
    n: usize,
    a: Vec<T>,
    piv: Vec<usize>,
}

/// The matrix was singular or contained non-finite entries.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Singular;

impl<T: Entry> Lu<T> {
    /// Storage for an `n x n` matrix, filled with `zero`.
    pub(crate) fn new(n: usize, zero: T) -> Self {
        Lu {
            n,
            a: vec![zero; n * n],
            piv: vec![0; n],
        }
    }

    /// Sets `A_ij = entry(i, j)` and factors it in place.
    pub(crate) fn factor(&mut self, entry: impl Fn(usize, usize) -> T) -> Result<(), Singular> {
        let n = self.n;
        for i in 0..n {
            for j in 0..n {
                self.a[i * n + j] = entry(i, j);
            }
        }
        for k in 0..n {
            let mut p = k;
            let mut big = self.a[k * n + k].magnitude();
            for i in k + 1..n {
                let m = self.a[i * n + k].magnitude();
                if m > big {
                    big = m;
                    p = i;
                }
            }
            if !(big > 0.0 && big.is_finite()) {
                return Err(Singular);
            }
            self.piv[k] = p;
            if p != k {
                for j in 0..n {
                    self.a.swap(k * n + j, p * n + j);
                }
            }
            let pivot = self.a[k * n + k];
            for i in k + 1..n {
                let l = self.a[i * n + k] / pivot;
                self.a[i * n + k] = l;
                for j in k + 1..n {
                    let u = self.a[k * n + j];
                    self.a[i * n + j] = self.a[i * n + j] - l * u;
                }
            }
        }
        if self.a.iter().all(|v| v.magnitude().is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }

    /// Overwrites `b` with `A^-1 b` (the factors must be current).
    pub(crate) fn solve(&self, b: &mut [T]) {
        let n = self.n;
        for k in 0..n {
            b.swap(k, self.piv[k]);
        }
        for i in 1..n {
            let row = &self.a[i * n..i * n + i];
            let s = row.iter().zip(&b[..i]).fold(b[i], |s, (&l, &x)| s - l * x);
            b[i] = s;
        }
        for i in (0..n).rev() {
            let row = &self.a[i * n + i + 1..(i + 1) * n];
            let s = row
                .iter()
                .zip(&b[i + 1..])
                .fold(b[i], |s, (&u, &x)| s - u * x);
            b[i] = s / self.a[i * n + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_real_and_complex_systems() {
        let m = [[0.0, 2.0, 1.0], [1.0, -1.0, 3.0], [4.0, 1.0, 0.5]];
        let x = [1.0, -2.0, 0.25];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| m[i][j] * x[j]).sum())
            .collect();
        let mut lu = Lu::new(3, 0.0);
        lu.factor(|i, j| m[i][j]).unwrap();
        lu.solve(&mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14);
        }
        let s = Complex64::new(0.5, 2.0);
        let xc: Vec<Complex64> = x.iter().map(|&v| Complex64::new(v, -v)).collect();
        let entry = |i: usize, j: usize| {
            Complex64::from(-m[i][j]) + if i == j { s } else { Complex64::from(0.0) }
        };
        let mut bc: Vec<Complex64> = (0..3)
            .map(|i| (0..3).map(|j| entry(i, j) * xc[j]).sum())
            .collect();
        let mut luc = Lu::new(3, Complex64::from(0.0));
        luc.factor(entry).unwrap();
        luc.solve(&mut bc);
        for i in 0..3 {
            assert!((bc[i] - xc[i]).norm() < 1e-14);
        }
        assert!(lu.factor(|_, _| 1.0).is_err());
        assert!(lu
            .factor(|i, j| if i == j { f64::NAN } else { 0.0 })
            .is_err());
    }
}
