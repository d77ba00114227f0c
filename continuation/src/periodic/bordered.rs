//! Structured factorization of the linearized collocation system:
//! condensation of the interior nodes interval by interval, then orthogonal
//! cyclic reduction of the mesh nodes, with the dense rows (phase condition,
//! arclength or fixed-parameter condition, test functions) carried through
//! every elimination — the strategy of AUTO's collocation solver (Doedel,
//! Keller & Kernévez 1991, "Numerical analysis and control of bifurcation
//! problems (II)", §5), here with Householder QR at every step instead of
//! Gaussian elimination.
//!
//! The system has `N = NTST m n` node unknowns `y` and `k` border unknowns
//! `x` (period, parameters, ...):
//!
//! ```text
//! [ C  E ] [ y ]   [ r_C ]      C: collocation rows on the nodes (block cyclic)
//! [ D  G ] [ x ] = [ r_D ]      E: border columns, D, G: k dense rows
//! ```
//!
//! The reduction ([`CyclicReduction`]) depends on `C` alone: row operations
//! `R` (a row equilibration and an orthogonal transformation per interval,
//! then one per eliminated node) make `R C` block upper triangular up to a
//! last `n x n` relation of node 0 with itself, the Floquet pencil. A
//! bordered system ([`Bordered`]) applies `R` to `E` and eliminates the
//! eliminated unknowns from the dense rows with multipliers `Lambda`, which
//! leaves the `(n + k)`-square system of node 0 and `x`. So
//! `(I - Lambda) R J P = U` is block upper triangular (`P` orders the
//! unknowns by elimination) and both `J z = r` (apply `R`, `Lambda`, back
//! substitution) and `J^T w = r` (forward substitution with `U^T`, then
//! `Lambda^T` and `R^T` in reverse order) are solved from one factorization.
//! Several bordered systems share the reduction of `C`.
//!
//! Cost: `O(NTST (m n)^3)` flops in small dense blocks for the reduction,
//! `O(NTST (m n)^2 k)` for the borders, no fill-in, no symbolic analysis.

use super::collocation::Linearization;
use crate::error::ContinuationError;
use nalgebra::{
    Const, DMatrix, DMatrixView, DVector, DVectorView, DVectorViewMut, Dyn, FullPivLU, SMatrix,
    SVector, U3, U4, U5, U6,
};
use smallvec::SmallVec;
use std::borrow::Cow;
use std::ops::Range;

/// Householder QR of a block with at least as many rows as columns,
/// `Q^T a = [r; 0]` with `Q = H_0 H_1 ... H_{c-1}`, `H_j = I - 2 v_j v_j^T`
/// (Golub & Van Loan, *Matrix Computations*, §5.2), the reflectors kept to
/// apply `Q^T` and `Q` to other columns.
#[derive(Clone, Debug)]
struct Householder {
    /// Unit reflector `v_j` in rows `j..` of column `j` (the rows above it
    /// are not used).
    v: DMatrix<f64>,
    /// The upper triangular factor (`c x c`).
    r: DMatrix<f64>,
}

impl Householder {
    fn zeros(rows: usize, cols: usize) -> Self {
        Householder {
            v: DMatrix::zeros(rows, cols),
            r: DMatrix::zeros(cols, cols),
        }
    }

    /// Factors the `rows x cols` block held in the first `cols` columns of
    /// the rows `w` (each `width` entries; [`Sweep`]) into the reflectors
    /// `self.v` and the factor `self.r`, and applies `Q^T` to the trailing
    /// columns beside it, each reflector as soon as it is formed. The sizes
    /// are passed in: a caller that knows them at compile time gets the
    /// loops unrolled.
    ///
    /// A reflector's dot products with the columns on its right are summed
    /// side by side, one lane a column, each in row order from `-0.0` — the
    /// sums of a reflection column by column, to the bit, in vector
    /// instructions across the columns. The lanes start at the group of
    /// [`LANES`] holding column `j + 1`; the columns before it in that group
    /// (already factored) are transformed too and never read again.
    #[inline(always)]
    fn factor(&mut self, w: &mut [f64], (rows, cols): (usize, usize), width: usize) {
        let w = &mut w[..rows * width];
        let r = &mut self.r.as_mut_slice()[..cols * cols];
        r.fill(0.0);
        let v_all = &mut self.v.as_mut_slice()[..rows * cols];
        for j in 0..cols {
            let v = &mut v_all[j * rows + j..(j + 1) * rows];
            for (k, vk) in v.iter_mut().enumerate() {
                *vk = w[(j + k) * width + j];
            }
            r[j * cols + j] = reflector_of(v);
            // x <- x - 2 (v . x) v for every column x right of column j, up
            // to GROUPS groups of lanes at a time.
            let mut first = (j + 1) / LANES * LANES;
            while first < width {
                let groups = ((width - first) / LANES).min(GROUPS);
                let rows = &mut w[j * width + first..];
                match groups {
                    1 => reflect_groups::<1>(rows, width, v),
                    2 => reflect_groups::<2>(rows, width, v),
                    3 => reflect_groups::<3>(rows, width, v),
                    4 => reflect_groups::<4>(rows, width, v),
                    5 => reflect_groups::<5>(rows, width, v),
                    _ => reflect_groups::<GROUPS>(rows, width, v),
                }
                first += groups * LANES;
            }
            for c in j + 1..cols {
                r[c * cols + j] = w[j * width + c];
            }
        }
    }

    /// `x <- Q^T x` (`x` has as many entries as the block has rows,
    /// `rows`; the block's `rows x cols` passed in: a caller that knows them
    /// at compile time gets the loops unrolled).
    #[inline(always)]
    fn apply_qt_sized(&self, x: &mut [f64], (rows, cols): (usize, usize)) {
        let v = &self.v.as_slice()[..rows * cols];
        let x = &mut x[..rows];
        for j in 0..cols {
            reflect(&v[j * rows + j..(j + 1) * rows], &mut x[j..]);
        }
    }

    /// `x <- Q x`.
    fn apply_q(&self, x: &mut [f64]) {
        for j in (0..self.v.ncols()).rev() {
            reflect(self.reflector(j), &mut x[j..]);
        }
    }

    fn reflector(&self, j: usize) -> &[f64] {
        let rows = self.v.nrows();
        &self.v.as_slice()[j * rows + j..(j + 1) * rows]
    }
}

/// The unit reflector `v` of the column `x` held in `v` (overwritten), with
/// `(I - 2 v v^T) x = alpha e_1`; returns `alpha`, of the sign opposite to
/// `x_1` (`v = x - alpha e_1` without cancellation).
#[inline(always)]
fn reflector_of(v: &mut [f64]) -> f64 {
    let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    let alpha = if v[0] >= 0.0 { -norm } else { norm };
    v[0] -= alpha;
    let size = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    if size > 0.0 {
        v.iter_mut().for_each(|a| *a /= size);
    }
    alpha
}

/// `x <- (I - 2 v v^T) x`.
fn reflect(v: &[f64], x: &mut [f64]) {
    macro_rules! fixed {
        ($($l:literal)*) => {
            match v.len() {
                $($l => reflect_one(<&[f64; $l]>::try_from(v).unwrap(), &mut x[..$l]),)*
                _ => reflect_one(v, x),
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// [`reflect`]'s arithmetic: the dot product summed in row order from
/// `-0.0` (where `Iterator::sum` starts too). Inlined into callers that
/// know `v`'s length at compile time, whose loops are then unrolled.
#[inline(always)]
fn reflect_one(v: &[f64], x: &mut [f64]) {
    let x = &mut x[..v.len()];
    let mut dot = -0.0f64;
    for r in 0..v.len() {
        dot += v[r] * x[r];
    }
    let f = 2.0 * dot;
    for r in 0..v.len() {
        x[r] -= f * v[r];
    }
}

/// Columns transformed side by side by [`Householder::factor`]: four
/// lanes of `f64`, two vector registers of the baseline x86-64 target.
const LANES: usize = 4;

/// Groups of [`LANES`] reflected in one pass over the reflector: their dot
/// products held in twelve vector registers.
const GROUPS: usize = 6;

/// `x <- x - 2 (v . x) v` for the `G` groups of [`LANES`] columns starting
/// `rows` (row-major, row stride `width`, `v.len()` rows): each column's dot
/// product summed in row order from `-0.0`, then its update.
#[inline(always)]
fn reflect_groups<const G: usize>(rows: &mut [f64], width: usize, v: &[f64]) {
    let mut dot = [[-0.0f64; LANES]; G];
    for (k, &vk) in v.iter().enumerate() {
        let (row, _) = rows[k * width..][..G * LANES].as_chunks::<LANES>();
        for (d, x) in dot.iter_mut().zip(row) {
            for l in 0..LANES {
                d[l] += vk * x[l];
            }
        }
    }
    let f = dot.map(|d| d.map(|d| 2.0 * d));
    for (k, &vk) in v.iter().enumerate() {
        let (row, _) = rows[k * width..][..G * LANES].as_chunks_mut::<LANES>();
        for (x, f) in row.iter_mut().zip(&f) {
            for l in 0..LANES {
                x[l] -= f[l] * vk;
            }
        }
    }
}

/// A block and its trailing columns side by side, row by row (`w`, each
/// row padded to whole [`LANES`] with columns that are never read), for
/// [`Householder::factor`].
#[derive(Clone, Debug, Default)]
struct Sweep {
    w: Vec<f64>,
    width: usize,
}

impl Sweep {
    /// Makes room for `rows` rows of `columns` columns (the block's and the
    /// trailing ones); the entries are the caller's to fill.
    fn shape(&mut self, rows: usize, columns: usize) {
        let width = padded(columns);
        if self.width != width || self.w.len() != rows * width {
            self.width = width;
            self.w = vec![0.0; rows * width];
        }
    }
}

/// The width of a [`Sweep`]'s rows of `columns` columns: whole [`LANES`].
#[inline(always)]
fn padded(columns: usize) -> usize {
    columns.div_ceil(LANES) * LANES
}

/// The `rows x cols` entries from `(r0, c0)` on of the rows `w` (each
/// `width` entries) into the column-major `target`.
#[inline(always)]
fn rows_into(
    w: &[f64],
    width: usize,
    (r0, c0): (usize, usize),
    (rows, cols): (usize, usize),
    target: &mut [f64],
) {
    let target = &mut target[..rows * cols];
    for c in 0..cols {
        for r in 0..rows {
            target[c * rows + r] = w[(r0 + r) * width + c0 + c];
        }
    }
}

/// The `rows x cols` entries from `(r0, c0)` on of the rows `w` (each
/// `width` entries) from the column-major `source`.
#[inline(always)]
fn rows_from(
    w: &mut [f64],
    width: usize,
    (r0, c0): (usize, usize),
    (rows, cols): (usize, usize),
    source: &[f64],
) {
    let source = &source[..rows * cols];
    for c in 0..cols {
        for r in 0..rows {
            w[(r0 + r) * width + c0 + c] = source[c * rows + r];
        }
    }
}

/// The condensation of one interval: row equilibration `s` (on stiff
/// stretches of an orbit one component's rows carry entries like
/// `h T A/(m v) ~ 1e12` next to O(1) ones, and reflections mixing them would
/// lose the small ones; scaling an equation changes neither the solution nor
/// the Floquet multipliers), then `Q^T` from the QR of the interior columns:
/// the first `(m - 1) n` rows, `r w + top [y_i; y_{i+1}] + ...`, recover the
/// interior `w`; the last `n` are the interval's relation `a y_i + b y_{i+1}`.
#[derive(Clone, Debug)]
struct Interval {
    scale: Vec<f64>,
    qr: Householder,
    top: DMatrix<f64>,
}

/// The elimination of node `node`, shared by the relation held in the rows
/// of interval `upper` (its right node) and that of `lower` (its left): `Q^T`
/// from the QR of `[b_upper; a_lower]` turns them into
/// `r y_node + x y_left + z y_right + ...` (kept in `upper`'s rows) and the
/// relation of `left` with `right` (in `lower`'s rows).
#[derive(Clone, Debug)]
struct NodeElimination {
    node: usize,
    left: usize,
    right: usize,
    upper: usize,
    lower: usize,
    qr: Householder,
    x: DMatrix<f64>,
    z: DMatrix<f64>,
}

/// The reduction `R` of the collocation rows on the mesh nodes (see the
/// module documentation): mesh node `i` is the first node of interval `i`.
#[derive(Clone, Debug)]
pub struct CyclicReduction {
    n: usize,
    m: usize,
    intervals: Vec<Interval>,
    eliminations: Vec<NodeElimination>,
    /// The relation `a y_left + b y_right` held in each interval's last `n`
    /// rows (of node 0 with itself, in interval `last`, at the end).
    a: Vec<DMatrix<f64>>,
    b: Vec<DMatrix<f64>>,
    last: usize,
    /// `R E` for the linearization's own border columns `E = (dF/dT,
    /// dF/dp_k)` (`N x 2`), transformed in the sweeps that form `R`.
    border: DMatrix<f64>,
    /// Scratch of [`CyclicReduction::factor`], kept so that a new
    /// factorization on a mesh of the same shape allocates nothing.
    scratch: FactorScratch,
}

/// Scratch of [`CyclicReduction::factor`]: an interval's block in rows, an
/// elimination's, and the chains of relations.
#[derive(Clone, Debug, Default)]
struct FactorScratch {
    sweep: Sweep,
    pairs: Sweep,
    chain: Vec<(usize, usize, usize)>,
    next: Vec<(usize, usize, usize)>,
}

impl CyclicReduction {
    /// The reduction of `lin`'s collocation rows (state dimension `n`).
    pub fn new(lin: &Linearization, n: usize) -> Self {
        let mut reduction = CyclicReduction {
            n,
            m: 0,
            intervals: Vec::new(),
            eliminations: Vec::new(),
            a: Vec::new(),
            b: Vec::new(),
            last: 0,
            border: DMatrix::zeros(0, BORDER),
            scratch: FactorScratch::default(),
        };
        reduction.factor(lin);
        reduction
    }

    /// Recomputes the reduction for `lin` (same state dimension), reusing
    /// the storage when the mesh has the same shape.
    pub fn factor(&mut self, lin: &Linearization) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, detected just above.
            return unsafe { self.factor_avx2(lin) };
        }
        self.factor_here(lin);
    }

    /// [`CyclicReduction::factor`] compiled for AVX2: the four lanes of
    /// [`Householder::factor`] in one vector register. No fused
    /// multiply-add (Rust does not contract `a * b + c`), so the same
    /// results to the bit.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn factor_avx2(&mut self, lin: &Linearization) {
        self.factor_here(lin);
    }

    /// [`CyclicReduction::factor`]'s work, inlined into each of its targets,
    /// and there once more for each of the common shapes (`n = 2, 3`,
    /// degree 4) with the sizes constant.
    #[inline(always)]
    fn factor_here(&mut self, lin: &Linearization) {
        let mn = lin.blocks.shape().0;
        match (self.n, mn) {
            (2, 8) => self.factor_shaped(lin, 2, 4),
            (3, 12) => self.factor_shaped(lin, 3, 4),
            (n, mn) => self.factor_shaped(lin, n, mn / n),
        }
    }

    /// [`CyclicReduction::factor_here`] for state dimension `n` and degree
    /// `m`.
    #[inline(always)]
    fn factor_shaped(&mut self, lin: &Linearization, n: usize, m: usize) {
        let ntst = lin.blocks.count();
        let mn = m * n;
        if self.m != m || self.intervals.len() != ntst {
            self.m = m;
            self.intervals = vec![
                Interval {
                    scale: vec![0.0; mn],
                    qr: Householder::zeros(mn, (m - 1) * n),
                    top: DMatrix::zeros((m - 1) * n, 2 * n),
                };
                ntst
            ];
            self.eliminations = vec![
                NodeElimination {
                    node: 0,
                    left: 0,
                    right: 0,
                    upper: 0,
                    lower: 0,
                    qr: Householder::zeros(2 * n, n),
                    x: DMatrix::zeros(n, n),
                    z: DMatrix::zeros(n, n),
                };
                ntst - 1
            ];
            self.a = vec![DMatrix::zeros(n, n); ntst];
            self.b = vec![DMatrix::zeros(n, n); ntst];
            self.border = DMatrix::zeros(ntst * mn, BORDER);
        }
        // Each interval's block in rows: its interior columns (factored),
        // then its end columns and its border columns (`Q^T` applied to
        // them as each reflector is formed), every row equilibrated.
        let mut scratch = std::mem::take(&mut self.scratch);
        let (interior, ends) = ((m - 1) * n, 2 * n + BORDER);
        let sweep = &mut scratch.sweep;
        sweep.shape(mn, interior + ends);
        let width = padded(interior + ends);
        let w = &mut sweep.w[..mn * width];
        let border_rows = ntst * mn;
        let border = self.border.as_mut_slice();
        for (i, (iv, data)) in self
            .intervals
            .iter_mut()
            .zip(lin.blocks.slices())
            .enumerate()
        {
            // Column-major: column c of the block is data[c mn..(c + 1) mn].
            let data = &data[..((m + 1) * n + BORDER) * mn];
            let column = |c: usize| &data[c * mn..(c + 1) * mn];
            let scale = &mut iv.scale[..mn];
            scale.fill(0.0);
            for c in 0..(m + 1) * n {
                for (s, v) in scale.iter_mut().zip(column(c)) {
                    *s = s.max(v.abs());
                }
            }
            for s in scale.iter_mut() {
                *s = if *s > 0.0 && s.is_finite() {
                    1.0 / *s
                } else {
                    1.0
                };
            }
            // Target column of each of the block's: interior, ends, border.
            let target = |c: usize| match c {
                c if c < n => interior + c,
                c if c < m * n => c - n,
                c => interior + n + c - m * n,
            };
            for c in 0..(m + 1) * n + BORDER {
                let t = target(c);
                for (r, (v, s)) in column(c).iter().zip(&*scale).enumerate() {
                    w[r * width + t] = s * v;
                }
            }
            iv.qr.factor(w, (mn, interior), width);
            rows_into(
                w,
                width,
                (0, interior),
                (interior, 2 * n),
                iv.top.as_mut_slice(),
            );
            rows_into(
                w,
                width,
                (interior, interior),
                (n, n),
                self.a[i].as_mut_slice(),
            );
            rows_into(
                w,
                width,
                (interior, interior + n),
                (n, n),
                self.b[i].as_mut_slice(),
            );
            for c in 0..BORDER {
                for r in 0..mn {
                    border[c * border_rows + i * mn + r] = w[r * width + interior + 2 * n + c];
                }
            }
        }
        // Orthogonal cyclic reduction: (interval holding the relation, left,
        // right); each elimination's block `[b_upper; a_lower]` in rows, then
        // the eliminated node's neighbours and the border rows.
        let (chain, next) = (&mut scratch.chain, &mut scratch.next);
        chain.clear();
        chain.extend((0..ntst).map(|i| (i, i, (i + 1) % ntst)));
        let pairs = &mut scratch.pairs;
        pairs.shape(2 * n, n + 2 * n + BORDER);
        let width = padded(n + 2 * n + BORDER);
        let p = &mut pairs.w[..2 * n * width];
        let mut count = 0;
        while chain.len() > 1 {
            next.clear();
            for pair in chain.chunks(2) {
                let &[(upper, left, node), (lower, _, right)] = pair else {
                    next.push(pair[0]);
                    continue;
                };
                let el = &mut self.eliminations[count];
                count += 1;
                (el.node, el.left, el.right, el.upper, el.lower) =
                    (node, left, right, upper, lower);
                let (upper_rows, lower_rows) = ((upper + 1) * mn - n, (lower + 1) * mn - n);
                rows_from(p, width, (0, 0), (n, n), self.b[upper].as_slice());
                rows_from(p, width, (n, 0), (n, n), self.a[lower].as_slice());
                rows_from(p, width, (0, n), (n, n), self.a[upper].as_slice());
                for r in 0..n {
                    p[r * width + 2 * n..][..n].fill(0.0);
                    p[(n + r) * width + n..][..n].fill(0.0);
                }
                rows_from(p, width, (n, 2 * n), (n, n), self.b[lower].as_slice());
                for c in 0..BORDER {
                    for r in 0..n {
                        p[r * width + 3 * n + c] = border[c * border_rows + upper_rows + r];
                        p[(n + r) * width + 3 * n + c] = border[c * border_rows + lower_rows + r];
                    }
                }
                el.qr.factor(p, (2 * n, n), width);
                rows_into(p, width, (0, n), (n, n), el.x.as_mut_slice());
                rows_into(p, width, (0, 2 * n), (n, n), el.z.as_mut_slice());
                rows_into(p, width, (n, n), (n, n), self.a[lower].as_mut_slice());
                rows_into(p, width, (n, 2 * n), (n, n), self.b[lower].as_mut_slice());
                for c in 0..BORDER {
                    for r in 0..n {
                        border[c * border_rows + upper_rows + r] = p[r * width + 3 * n + c];
                        border[c * border_rows + lower_rows + r] = p[(n + r) * width + 3 * n + c];
                    }
                }
                next.push((lower, left, right));
            }
            std::mem::swap(chain, next);
        }
        self.last = chain[0].0;
        self.scratch = scratch;
    }

    /// `R E` for the linearization's own border columns `E = (dF/dT,
    /// dF/dp_k)` (`N x 2`), transformed in the sweeps that formed `R`.
    pub fn border(&self) -> &DMatrix<f64> {
        &self.border
    }

    /// The last relation `a y_0 + b y_N = 0` (`y_N = y_0` for the orbit): the
    /// Floquet pencil `a y = mu (-b) y`.
    pub fn pencil(&self) -> (&DMatrix<f64>, &DMatrix<f64>) {
        (&self.a[self.last], &self.b[self.last])
    }

    /// The state dimension `n`.
    pub fn dim(&self) -> usize {
        self.n
    }

    fn mn(&self) -> usize {
        self.m * self.n
    }

    /// Rows (and interior unknowns) of interval `i` recovering its interior.
    fn top_rows(&self, i: usize) -> Range<usize> {
        i * self.mn()..i * self.mn() + (self.m - 1) * self.n
    }

    /// Rows holding interval `i`'s relation (or an elimination, once used).
    fn relation_rows(&self, i: usize) -> Range<usize> {
        (i + 1) * self.mn() - self.n..(i + 1) * self.mn()
    }

    /// Unknowns of mesh node `i`.
    fn node(&self, i: usize) -> Range<usize> {
        i * self.mn()..i * self.mn() + self.n
    }

    /// `x <- R x` on the collocation rows.
    pub fn apply_r(&self, x: &mut [f64]) {
        match (self.n, self.m) {
            (2, 4) => self.apply_r_shaped(x, (2, 4)),
            (3, 4) => self.apply_r_shaped(x, (3, 4)),
            shape => self.apply_r_shaped(x, shape),
        }
    }

    /// [`CyclicReduction::apply_r`] for the state dimension and degree
    /// `(n, m)`, inlined once more for each of the common shapes with the
    /// sizes constant.
    #[inline(always)]
    fn apply_r_shaped(&self, x: &mut [f64], (n, m): (usize, usize)) {
        let mn = m * n;
        for (i, iv) in self.intervals.iter().enumerate() {
            let rows = &mut x[i * mn..(i + 1) * mn];
            rows.iter_mut()
                .zip(&iv.scale[..mn])
                .for_each(|(a, s)| *a *= s);
            iv.qr.apply_qt_sized(rows, (mn, (m - 1) * n));
        }
        let mut pair = SmallVec::<[f64; 16]>::from_elem(0.0, 2 * n);
        for el in &self.eliminations {
            self.gather(x, el, &mut pair);
            el.qr.apply_qt_sized(&mut pair, (2 * n, n));
            self.scatter(&pair, el, x);
        }
    }

    /// `x <- R^T x` on the collocation rows.
    fn apply_rt(&self, x: &mut [f64]) {
        let mut pair = SmallVec::<[f64; 16]>::from_elem(0.0, 2 * self.n);
        for el in self.eliminations.iter().rev() {
            self.gather(x, el, &mut pair);
            el.qr.apply_q(&mut pair);
            self.scatter(&pair, el, x);
        }
        let mn = self.mn();
        for (i, iv) in self.intervals.iter().enumerate() {
            let rows = &mut x[i * mn..(i + 1) * mn];
            iv.qr.apply_q(rows);
            rows.iter_mut().zip(&iv.scale).for_each(|(a, s)| *a *= s);
        }
    }

    fn gather(&self, x: &[f64], el: &NodeElimination, pair: &mut [f64]) {
        let n = self.n;
        pair[..n].copy_from_slice(&x[self.relation_rows(el.upper)]);
        pair[n..].copy_from_slice(&x[self.relation_rows(el.lower)]);
    }

    fn scatter(&self, pair: &[f64], el: &NodeElimination, x: &mut [f64]) {
        let n = self.n;
        x[self.relation_rows(el.upper)].copy_from_slice(&pair[..n]);
        x[self.relation_rows(el.lower)].copy_from_slice(&pair[n..]);
    }
}

/// The collocation system bordered by `k` columns and `k` dense rows,
/// factored on a [`CyclicReduction`]: solves with the matrix and with its
/// transpose.
pub struct Bordered<'a> {
    reduction: &'a CyclicReduction,
    /// `R E`: the border columns transformed (`N x k`); borrowed when they
    /// are the reduction's own ([`Bordered::on_border`]).
    columns: Cow<'a, DMatrix<f64>>,
    /// The multipliers, the final system, its LU and the solves' scratch.
    store: BorderedStore,
}

/// The storage of a [`Bordered`] system: kept by its owner
/// ([`Bordered::into_store`]) so that the next system of the same shape
/// (the next Newton iteration on one mesh) allocates nothing.
#[derive(Clone, Debug, Default)]
pub struct BorderedStore {
    /// `Lambda^T`, the dense rows' multipliers, per interval (`(m - 1) n x k`)
    /// and per node elimination (`n x k`).
    interior: Vec<DMatrix<f64>>,
    nodes: Vec<DMatrix<f64>>,
    /// The final system in `(y_0, x)` and its LU.
    last: DMatrix<f64>,
    lu: Option<SmallLu>,
    /// Scratch of [`Bordered::solve_into`].
    c: Vec<f64>,
    g: DVector<f64>,
    y: Vec<f64>,
    w: Vec<f64>,
}

/// `FullPivLU` of the final `(n + k)`-square system, on the stack for the
/// sizes that occur (`n = 1, 2, 3` with `k = 2`; `n = 2, 3` with `k = 3`):
/// the same algorithm as the dynamic one, so the same results to the bit.
#[derive(Clone, Debug)]
enum SmallLu {
    L3(FullPivLU<f64, U3, U3>),
    L4(FullPivLU<f64, U4, U4>),
    L5(FullPivLU<f64, U5, U5>),
    L6(FullPivLU<f64, U6, U6>),
    Dynamic(FullPivLU<f64, Dyn, Dyn>),
}

impl SmallLu {
    fn new(last: &DMatrix<f64>) -> Self {
        match last.nrows() {
            3 => {
                SmallLu::L3(SMatrix::<f64, 3, 3>::from_column_slice(last.as_slice()).full_piv_lu())
            }
            4 => {
                SmallLu::L4(SMatrix::<f64, 4, 4>::from_column_slice(last.as_slice()).full_piv_lu())
            }
            5 => {
                SmallLu::L5(SMatrix::<f64, 5, 5>::from_column_slice(last.as_slice()).full_piv_lu())
            }
            6 => {
                SmallLu::L6(SMatrix::<f64, 6, 6>::from_column_slice(last.as_slice()).full_piv_lu())
            }
            _ => SmallLu::Dynamic(last.clone().full_piv_lu()),
        }
    }

    /// `g <- A^{-1} g`; `false` when `A` is singular.
    fn solve_mut(&self, g: &mut DVector<f64>) -> bool {
        self.solve_either(g, false)
    }

    /// `g <- A^{-T} g` from the same factors; `false` when `A` is singular.
    fn solve_transpose_mut(&self, g: &mut DVector<f64>) -> bool {
        self.solve_either(g, true)
    }

    /// `g <- A^{-1} g`, or `A^{-T} g` with `transpose`. With `P A Q = L U`
    /// (nalgebra's `FullPivLU`: `A^{-1} = Q U^{-1} L^{-1} P`),
    /// `A^{-T} = P^T L^{-T} U^{-T} Q^T`.
    fn solve_either(&self, g: &mut DVector<f64>, transpose: bool) -> bool {
        fn fixed<const D: usize>(
            lu: &FullPivLU<f64, Const<D>, Const<D>>,
            g: &mut DVector<f64>,
            transpose: bool,
        ) -> bool
        where
            Const<D>: nalgebra::DimMin<Const<D>, Output = Const<D>>,
        {
            let mut b = SVector::<f64, D>::from_column_slice(g.as_slice());
            let ok = if transpose {
                lu.q().permute_rows(&mut b);
                let ok = lu.u().tr_solve_upper_triangular_mut(&mut b)
                    && lu.l().tr_solve_lower_triangular_mut(&mut b);
                lu.p().inv_permute_rows(&mut b);
                ok
            } else {
                lu.solve_mut(&mut b)
            };
            g.copy_from_slice(b.as_slice());
            ok
        }
        match self {
            SmallLu::L3(lu) => fixed(lu, g, transpose),
            SmallLu::L4(lu) => fixed(lu, g, transpose),
            SmallLu::L5(lu) => fixed(lu, g, transpose),
            SmallLu::L6(lu) => fixed(lu, g, transpose),
            SmallLu::Dynamic(lu) if transpose => {
                lu.q().permute_rows(g);
                let ok = lu.u().tr_solve_upper_triangular_mut(g)
                    && lu.l().tr_solve_lower_triangular_mut(g);
                lu.p().inv_permute_rows(g);
                ok
            }
            SmallLu::Dynamic(lu) => lu.solve_mut(g),
        }
    }
}

/// `target` holds a matrix of shape `shape` (its entries arbitrary), reusing its storage.
pub(super) fn shaped(target: &mut DMatrix<f64>, (rows, cols): (usize, usize)) {
    if target.shape() != (rows, cols) {
        *target = DMatrix::zeros(rows, cols);
    }
}

/// `a . b` for vectors of dynamic size, summed as nalgebra sums them
/// (eight partial sums over whole groups of eight entries, added pairwise,
/// then the rest in order): the elimination of the dense rows below gives
/// the results of nalgebra's `gemm_tr`, `gemv` and triangular solves, to
/// the bit, on slices whose sizes the shapes that occur make constants.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let b = &b[..a.len()];
    let mut acc = [0.0f64; 8];
    let groups = a.len() / 8 * 8;
    for (x, y) in a[..groups].chunks_exact(8).zip(b[..groups].chunks_exact(8)) {
        for l in 0..8 {
            acc[l] += x[l] * y[l];
        }
    }
    let mut sum = 0.0;
    for l in 0..4 {
        sum += acc[l] + acc[l + 4];
    }
    for (x, y) in a[groups..].iter().zip(&b[groups..]) {
        sum += x * y;
    }
    sum
}

/// `out <- out - lt^T b`: `out` is `k x q` (column-major), `lt` is `len x
/// k`, column `c` of `b` (`len` entries) is `b(c)`.
#[inline(always)]
fn subtract_products<'b>(
    out: &mut [f64],
    k: usize,
    (lt, len): (&[f64], usize),
    b: impl Fn(usize) -> &'b [f64],
) {
    for (c, column) in out.chunks_exact_mut(k).enumerate() {
        let b = &b(c)[..len];
        for (j, o) in column.iter_mut().enumerate() {
            *o -= dot(&lt[j * len..(j + 1) * len], b);
        }
    }
}

/// `w <- w - a x` for the column-major `a` of `w.len()` rows, column `c`
/// at `a(c)`, `x` of as many entries as `a` has columns.
#[inline(always)]
fn subtract_product<'a>(w: &mut [f64], a: impl Fn(usize) -> &'a [f64], x: &[f64]) {
    for (c, xc) in x.iter().enumerate() {
        for (wr, ar) in w.iter_mut().zip(a(c)) {
            *wr -= ar * xc;
        }
    }
}

/// `y <- r^{-1} y` for the upper triangular `r` (column-major, `y.len()`
/// square), by back substitution; `false` on a zero pivot.
#[inline(always)]
fn back_substitute(r: &[f64], y: &mut [f64]) -> bool {
    let dim = y.len();
    for i in (0..dim).rev() {
        let diag = r[i * dim + i];
        if diag == 0.0 {
            return false;
        }
        let coeff = y[i] / diag;
        y[i] = coeff;
        for (yl, rl) in y[..i].iter_mut().zip(&r[i * dim..i * dim + i]) {
            *yl -= coeff * rl;
        }
    }
    true
}

/// The multipliers `lt = Lambda^T` that eliminate the unknowns
/// `start..start + len` (pivot block `r`, upper triangular, column-major)
/// from the `k` dense rows `rows` (column-major, column `c` at
/// `rows[c k..]`): `r^T lt = rows[:, start..start + len]^T` by forward
/// substitution.
#[inline(always)]
fn multipliers(
    rows: &[f64],
    k: usize,
    (start, len): (usize, usize),
    r: &[f64],
    lt: &mut DMatrix<f64>,
) -> Result<(), ContinuationError> {
    shaped(lt, (len, k));
    let lt = lt.as_mut_slice();
    for l in 0..len {
        for j in 0..k {
            lt[j * len + l] = rows[(start + l) * k + j];
        }
    }
    for column in lt.chunks_exact_mut(len) {
        for i in 0..len {
            let d = dot(&r[i * len..i * len + i], &column[..i]);
            let diag = r[i * len + i];
            if diag == 0.0 {
                return Err(ContinuationError::Singular);
            }
            column[i] = (column[i] - d) / diag;
        }
    }
    Ok(())
}

/// Rows `start..start + len` of the border columns `columns` (`N x k`,
/// column-major), column by column.
#[inline(always)]
fn border_rows<'a>(
    columns: &'a DMatrix<f64>,
    start: usize,
    len: usize,
) -> impl Fn(usize) -> &'a [f64] + 'a {
    let nn = columns.nrows();
    let border = columns.as_slice();
    move |c| &border[c * nn + start..][..len]
}

/// Eliminates the reduction's unknowns from the `k` dense rows `rows`
/// (`k x (N + k)`), in the order of the reduction, keeping the
/// multipliers in `store`: `rows -= lambda (r y_cols + ...)` with `lambda =
/// rows_cols r^{-1}` for each interval's interior, then each eliminated
/// node. `(n, m, k)` are the state dimension, the degree and the border.
#[inline(always)]
fn eliminate_dense(
    reduction: &CyclicReduction,
    columns: &DMatrix<f64>,
    rows: &mut DMatrix<f64>,
    store: &mut BorderedStore,
    (n, m, k): (usize, usize, usize),
) -> Result<(), ContinuationError> {
    let mn = m * n;
    let ntst = reduction.intervals.len();
    let nn = ntst * mn;
    let interior = (m - 1) * n;
    let rows = rows.as_mut_slice();
    let intervals = if m > 1 { ntst } else { 0 };
    store.interior.resize_with(intervals, DMatrix::default);
    for (i, (iv, lt)) in reduction
        .intervals
        .iter()
        .zip(store.interior.iter_mut())
        .enumerate()
    {
        let top = i * mn;
        multipliers(rows, k, (top + n, interior), iv.qr.r.as_slice(), lt)?;
        let lt = (lt.as_slice(), interior);
        let t = iv.top.as_slice();
        let next = (i + 1) % ntst;
        subtract_products(&mut rows[i * mn * k..][..n * k], k, lt, |c| {
            &t[c * interior..][..interior]
        });
        subtract_products(&mut rows[next * mn * k..][..n * k], k, lt, |c| {
            &t[(n + c) * interior..][..interior]
        });
        subtract_products(
            &mut rows[nn * k..][..k * k],
            k,
            lt,
            border_rows(columns, top, interior),
        );
    }
    store
        .nodes
        .resize_with(reduction.eliminations.len(), DMatrix::default);
    for (el, lt) in reduction.eliminations.iter().zip(store.nodes.iter_mut()) {
        multipliers(rows, k, (el.node * mn, n), el.qr.r.as_slice(), lt)?;
        let lt = (lt.as_slice(), n);
        let (x, z) = (el.x.as_slice(), el.z.as_slice());
        subtract_products(&mut rows[el.left * mn * k..][..n * k], k, lt, |c| {
            &x[c * n..][..n]
        });
        subtract_products(&mut rows[el.right * mn * k..][..n * k], k, lt, |c| {
            &z[c * n..][..n]
        });
        let relation = reduction.relation_rows(el.upper).start;
        subtract_products(
            &mut rows[nn * k..][..k * k],
            k,
            lt,
            border_rows(columns, relation, n),
        );
    }
    Ok(())
}

/// [`Bordered::solve_into`] after `R` (`store.c`, `N + k` entries, and the
/// final system's right-hand side in `store.g`): the dense rows'
/// elimination applied to the right-hand side, the final system solved,
/// then back substitution through the node eliminations in reverse and
/// each interval's interior, into `z`.
#[inline(always)]
fn substitute(
    red: &CyclicReduction,
    columns: &DMatrix<f64>,
    store: &mut BorderedStore,
    z: &mut Vec<f64>,
    (n, m, k): (usize, usize, usize),
) -> Result<(), ContinuationError> {
    let mn = m * n;
    let nn = columns.nrows();
    let interior = (m - 1) * n;
    let BorderedStore {
        interior: lts,
        nodes,
        lu,
        c,
        g,
        y,
        w,
        ..
    } = store;
    let c = &c[..nn + k];
    // The dense rows' right-hand side: `g_x -= lambda c`, one dot product
    // per dense row (through `subtract_products` with one column the
    // compiler kept the column loop: job 4 spent 0.53 G instructions more).
    let dense = |g: &mut [f64], lt: &[f64], rows: &[f64]| {
        let len = rows.len();
        for (j, gj) in g[n..n + k].iter_mut().enumerate() {
            *gj -= dot(&lt[j * len..(j + 1) * len], rows);
        }
    };
    for (i, lt) in lts.iter().enumerate() {
        dense(g.as_mut_slice(), lt.as_slice(), &c[i * mn..][..interior]);
    }
    for (el, lt) in red.eliminations.iter().zip(nodes.iter()) {
        let rows = red.relation_rows(el.upper).start;
        dense(g.as_mut_slice(), lt.as_slice(), &c[rows..][..n]);
    }
    let lu = lu.as_ref().expect("factored in `reduced`");
    if !lu.solve_mut(g) {
        return Err(ContinuationError::Singular);
    }
    let g = g.as_slice();
    z.clear();
    z.resize(nn + k, 0.0);
    z[..n].copy_from_slice(&g[..n]);
    z[nn..].copy_from_slice(&g[n..n + k]);
    let x = &g[n..n + k];
    // r y = c - (x y_left + z y_right + (R E) x), eliminations in reverse.
    y.resize(n, 0.0);
    let y = &mut y[..n];
    for el in red.eliminations.iter().rev() {
        let rows = red.relation_rows(el.upper).start;
        y.copy_from_slice(&c[rows..][..n]);
        let (ex, ez) = (el.x.as_slice(), el.z.as_slice());
        subtract_product(y, |c| &ex[c * n..][..n], &z[el.left * mn..][..n]);
        subtract_product(y, |c| &ez[c * n..][..n], &z[el.right * mn..][..n]);
        subtract_product(y, border_rows(columns, rows, n), x);
        if !back_substitute(el.qr.r.as_slice(), y) {
            return Err(ContinuationError::Singular);
        }
        z[el.node * mn..][..n].copy_from_slice(y);
    }
    if m > 1 {
        let ntst = red.intervals.len();
        w.resize(interior, 0.0);
        let w = &mut w[..interior];
        for (i, iv) in red.intervals.iter().enumerate() {
            let top = i * mn;
            w.copy_from_slice(&c[top..][..interior]);
            let t = iv.top.as_slice();
            let next = (i + 1) % ntst;
            subtract_product(w, |c| &t[c * interior..][..interior], &z[top..][..n]);
            subtract_product(
                w,
                |c| &t[(n + c) * interior..][..interior],
                &z[next * mn..][..n],
            );
            subtract_product(w, border_rows(columns, top, interior), x);
            if !back_substitute(iv.qr.r.as_slice(), w) {
                return Err(ContinuationError::Singular);
            }
            z[top + n..][..interior].copy_from_slice(w);
        }
    }
    Ok(())
}

impl<'a> Bordered<'a> {
    /// The system whose border columns are those of the linearization
    /// `reduction` was factored from (`dF/dT`, `dF/dp_k`), already
    /// transformed by `R` in its sweeps; `rows` `= [D G]` (`2 x (N + 2)`),
    /// overwritten. The system keeps `store`'s storage
    /// ([`Bordered::into_store`] gives it back).
    pub fn on_border(
        reduction: &'a CyclicReduction,
        rows: &mut DMatrix<f64>,
        store: BorderedStore,
    ) -> Result<Self, ContinuationError> {
        Self::reduced(reduction, Cow::Borrowed(&reduction.border), rows, store)
    }

    /// The system `[C E; D G]` with `R E` given (`columns`, `N x k`: the
    /// reduction's own [`CyclicReduction::border`] columns, or columns
    /// transformed by [`CyclicReduction::apply_r`]) and `rows` `= [D G]`
    /// (`k x (N + k)`), overwritten; in `store`'s storage.
    pub fn transformed(
        reduction: &'a CyclicReduction,
        columns: &'a DMatrix<f64>,
        rows: &mut DMatrix<f64>,
        store: BorderedStore,
    ) -> Result<Self, ContinuationError> {
        Self::reduced(reduction, Cow::Borrowed(columns), rows, store)
    }

    /// The system [`Bordered::on_border`] last reduced into `store` on
    /// `reduction`, again (the same dense rows: nothing to reduce).
    pub fn reused(reduction: &'a CyclicReduction, store: BorderedStore) -> Self {
        Bordered {
            reduction,
            columns: Cow::Borrowed(&reduction.border),
            store,
        }
    }

    /// The storage, for the next system.
    pub fn into_store(self) -> BorderedStore {
        self.store
    }

    /// The system with the border columns `R E` already transformed.
    fn reduced(
        reduction: &'a CyclicReduction,
        columns: Cow<'a, DMatrix<f64>>,
        rows: &mut DMatrix<f64>,
        mut store: BorderedStore,
    ) -> Result<Self, ContinuationError> {
        let (n, mn) = (reduction.n, reduction.mn());
        let ntst = reduction.intervals.len();
        let nn = ntst * mn;
        let k = columns.ncols();
        if columns.nrows() != nn || rows.shape() != (k, nn + k) {
            return Err(ContinuationError::Sparse(format!(
                "{} dense rows for {k} border columns",
                rows.nrows()
            )));
        }
        match (n, reduction.m, k) {
            (2, 4, 2) => eliminate_dense(reduction, &columns, rows, &mut store, (2, 4, 2))?,
            (3, 4, 2) => eliminate_dense(reduction, &columns, rows, &mut store, (3, 4, 2))?,
            shape => eliminate_dense(reduction, &columns, rows, &mut store, shape)?,
        }
        // Final system in (y_0, x): [a + b, R E; D_0, G].
        let (a, b) = reduction.pencil();
        let last = &mut store.last;
        shaped(last, (n + k, n + k));
        let mut top_left = last.view_mut((0, 0), (n, n));
        top_left.copy_from(a);
        top_left += b;
        let f = reduction.relation_rows(reduction.last);
        last.view_mut((0, n), (n, k))
            .copy_from(&columns.rows(f.start, n));
        last.view_mut((n, 0), (k, n)).copy_from(&rows.columns(0, n));
        last.view_mut((n, n), (k, k))
            .copy_from(&rows.columns(nn, k));
        store.lu = Some(SmallLu::new(last));
        Ok(Bordered {
            reduction,
            columns,
            store,
        })
    }

    fn dim(&self) -> usize {
        self.columns.nrows() + self.columns.ncols()
    }

    /// `Ok` when `v` has one entry per unknown of the system.
    fn check(&self, what: &'static str, v: &[f64]) -> Result<(), ContinuationError> {
        shape(what, self.dim(), v)
    }

    /// Solves `J z = rhs` (`rhs`: the collocation rows, then the dense rows;
    /// `z`: the node values, node-major, then the `k` border unknowns).
    pub fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        let mut z = Vec::new();
        self.solve_into(rhs, &mut z)?;
        Ok(z)
    }

    /// [`Bordered::solve`] into `z`, in the system's storage: no allocation
    /// once `z` and the storage have the system's size.
    pub fn solve_into(&mut self, rhs: &[f64], z: &mut Vec<f64>) -> Result<(), ContinuationError> {
        let shape = (self.reduction.n, self.reduction.m, self.columns.ncols());
        match shape {
            (2, 4, 2) => self.solve_shaped(rhs, z, (2, 4, 2)),
            (3, 4, 2) => self.solve_shaped(rhs, z, (3, 4, 2)),
            _ => self.solve_shaped(rhs, z, shape),
        }
    }

    /// [`Bordered::solve_into`] for the shape `(n, m, k)` (state dimension,
    /// degree, border), inlined once more for each of the common shapes with
    /// the sizes constant.
    #[inline(always)]
    fn solve_shaped(
        &mut self,
        rhs: &[f64],
        z: &mut Vec<f64>,
        shape: (usize, usize, usize),
    ) -> Result<(), ContinuationError> {
        self.check("the right-hand side", rhs)?;
        let red = self.reduction;
        let (n, nn, k) = (red.n, self.columns.nrows(), self.columns.ncols());
        let store = &mut self.store;
        let c = &mut store.c;
        c.clear();
        c.extend_from_slice(rhs);
        red.apply_r(&mut c[..nn]);
        let g = &mut store.g;
        if g.len() != n + k {
            *g = DVector::zeros(n + k);
        }
        g.rows_mut(0, n)
            .copy_from_slice(&c[red.relation_rows(red.last)]);
        g.rows_mut(n, k).copy_from_slice(&c[nn..]);
        substitute(red, &self.columns, store, z, shape)?;
        if z.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(ContinuationError::Singular)
        }
    }

    /// Solves `J^T w = rhs` (`rhs` indexed by the unknowns, `w` by the
    /// equations: collocation rows, then dense rows).
    pub fn solve_transpose(&self, rhs: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        self.check("the right-hand side", rhs)?;
        let red = self.reduction;
        let (n, nn, k) = (red.n, self.columns.nrows(), self.columns.ncols());
        let ntst = red.intervals.len();
        let mut t = rhs.to_vec();
        let mut s = vec![0.0; self.dim()];
        // U^T s = P^T rhs, unknowns in the order of elimination: the columns
        // of an eliminated group hold its pivot and rows eliminated before it.
        let push = |t: &mut [f64], range: Range<usize>, m: DMatrixView<f64>, s: &[f64]| {
            let mut target = DVectorViewMut::from_slice(&mut t[range.clone()], range.len());
            target.gemv_tr(-1.0, &m, &DVectorView::from_slice(s, s.len()), 1.0);
        };
        if red.m > 1 {
            for (i, iv) in red.intervals.iter().enumerate() {
                let rows = red.top_rows(i);
                let mut st = DVector::from_column_slice(&t[rows.start + n..rows.end + n]);
                if !iv.qr.r.tr_solve_upper_triangular_mut(&mut st) {
                    return Err(ContinuationError::Singular);
                }
                push(&mut t, red.node(i), iv.top.columns(0, n), st.as_slice());
                push(
                    &mut t,
                    red.node((i + 1) % ntst),
                    iv.top.columns(n, n),
                    st.as_slice(),
                );
                push(
                    &mut t,
                    nn..nn + k,
                    self.columns.rows(rows.start, rows.len()),
                    st.as_slice(),
                );
                s[rows].copy_from_slice(st.as_slice());
            }
        }
        for el in &red.eliminations {
            let rows = red.relation_rows(el.upper);
            let mut su = DVector::from_column_slice(&t[red.node(el.node)]);
            if !el.qr.r.tr_solve_upper_triangular_mut(&mut su) {
                return Err(ContinuationError::Singular);
            }
            push(&mut t, red.node(el.left), el.x.as_view(), su.as_slice());
            push(&mut t, red.node(el.right), el.z.as_view(), su.as_slice());
            push(
                &mut t,
                nn..nn + k,
                self.columns.rows(rows.start, n),
                su.as_slice(),
            );
            s[rows].copy_from_slice(su.as_slice());
        }
        let mut g = DVector::zeros(n + k);
        g.rows_mut(0, n).copy_from_slice(&t[..n]);
        g.rows_mut(n, k).copy_from_slice(&t[nn..]);
        let lu = self.store.lu.as_ref().expect("factored in `reduced`");
        if !lu.solve_transpose_mut(&mut g) {
            return Err(ContinuationError::Singular);
        }
        let sol = g;
        s[red.relation_rows(red.last)].copy_from_slice(sol.rows(0, n).as_slice());
        s[nn..].copy_from_slice(sol.rows(n, k).as_slice());
        // w = R^T (I - Lambda)^T s.
        let sd = sol.rows(n, k);
        let mut lambda = |rows: Range<usize>, lt: &DMatrix<f64>| {
            DVectorViewMut::from_slice(&mut s[rows.clone()], rows.len()).gemv(-1.0, lt, &sd, 1.0);
        };
        for (i, lt) in self.store.interior.iter().enumerate() {
            lambda(red.top_rows(i), lt);
        }
        for (el, lt) in red.eliminations.iter().zip(&self.store.nodes) {
            lambda(red.relation_rows(el.upper), lt);
        }
        red.apply_rt(&mut s[..nn]);
        finite(s)
    }
}

/// Border columns of a linearization: `dF/dT` and `dF/dp_k`, the last two
/// columns of every interval block.
const BORDER: usize = 2;

/// `Ok` when `v`, named `what` in the error, has `expected` entries: a
/// vector from another mesh is an error, never a panic inside the algebra.
pub fn shape(what: &'static str, expected: usize, v: &[f64]) -> Result<(), ContinuationError> {
    if v.len() == expected {
        Ok(())
    } else {
        Err(ContinuationError::Shape {
            what,
            expected,
            found: v.len(),
        })
    }
}

fn finite(x: Vec<f64>) -> Result<Vec<f64>, ContinuationError> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(x)
    } else {
        Err(ContinuationError::Singular)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::periodic::collocation::Blocks;
    use crate::periodic::newton::OrbitJacobian;

    /// A small deterministic pseudo-random sequence in (-1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// A random collocation-shaped system with `k` border columns and `k`
    /// dense rows (the first one the phase condition, on the nodes only):
    /// its linearization and the assembled matrix.
    fn random_system(
        seed: &mut u64,
        (n, m, ntst, k): (usize, usize, usize, usize),
    ) -> (Linearization, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
        let mn = m * n;
        let nn = ntst * mn;
        let dim = nn + k;
        // Interval blocks: `m n` rows on the `m + 1` nodes, then T and p.
        let locals: Vec<DMatrix<f64>> = (0..ntst)
            .map(|_| {
                DMatrix::from_fn(mn, (m + 1) * n + 2, |r, c| {
                    // Diagonally weighted so the assembled matrix is well conditioned.
                    let d = if c == r + n / 2 { 4.0 } else { 0.0 };
                    d + noise(seed)
                })
            })
            .collect();
        let mut dense = DMatrix::from_fn(k, dim, |_, _| noise(seed));
        dense.view_mut((0, nn), (1, k)).fill(0.0);
        let lin = Linearization {
            residual: Vec::new(),
            blocks: Blocks::from_matrices(&locals),
            phase: dense.row(0).columns(0, nn).iter().copied().collect(),
            term_scale: 0.0,
            trace_integral: 0.0,
            ..Default::default()
        };
        // Border columns: T and p (as many as there are), then random ones.
        let mut columns = DMatrix::from_fn(nn, k, |_, _| noise(seed));
        let j = k.min(2);
        columns
            .columns_mut(0, j)
            .copy_from(&lin.border_columns().columns(0, j));
        let mut full = DMatrix::zeros(dim, dim);
        for i in 0..ntst {
            let b = lin.blocks.block(i);
            for r in 0..mn {
                for l in 0..=m {
                    let node = (i * m + l) % (ntst * m);
                    for c in 0..n {
                        full[(i * mn + r, node * n + c)] += b[(r, l * n + c)];
                    }
                }
            }
        }
        full.view_mut((0, nn), (nn, k)).copy_from(&columns);
        full.rows_mut(nn, k).copy_from(&dense);
        (lin, columns, dense, full)
    }

    const SHAPES: [(usize, usize, usize); 6] = [
        (2, 1, 2),
        (3, 4, 5),
        (2, 3, 8),
        (3, 2, 7),
        (3, 4, 1),
        (2, 4, 3),
    ];

    #[test]
    fn condensed_cyclic_solve_matches_a_dense_solve() {
        let mut seed = 7;
        for (n, m, ntst) in SHAPES {
            let (lin, _, dense, full) = random_system(&mut seed, (n, m, ntst, 2));
            let dim = full.nrows();
            let rhs: Vec<f64> = (0..dim).map(|_| noise(&mut seed)).collect();
            let reference = full
                .full_piv_lu()
                .solve(&DVector::from_column_slice(&rhs))
                .unwrap();
            // The structured solve, as Newton's method calls it.
            let extra: Vec<f64> = dense.row(1).iter().copied().collect();
            let x = OrbitJacobian::new(lin, n).solve(&extra, &rhs).unwrap();
            let scale = reference.amax();
            for (a, b) in x.iter().zip(reference.iter()) {
                assert!(
                    (a - b).abs() < 1e-12 * scale,
                    "n {n} m {m} ntst {ntst}: {a} vs {b}"
                );
            }
        }
    }

    /// `dot` is nalgebra's dot product of vectors of dynamic size to the
    /// bit (lengths 0 to 20, entries of very different sizes); the dense
    /// rows' elimination and the solve compiled with their sizes constant
    /// (`n = 2, 3`, degree 4, `k = 2`) are the code for any size, entry by
    /// entry.
    #[test]
    fn the_dense_rows_eliminated_with_sizes_constant_are_the_code_for_any_size() {
        let mut seed = 17;
        for len in 0..=20 {
            let a: Vec<f64> = (0..len)
                .map(|i| noise(&mut seed) * 10f64.powi((i % 5) * 4 - 8))
                .collect();
            let b: Vec<f64> = (0..len).map(|_| noise(&mut seed)).collect();
            let expected = DVector::from_column_slice(&a).dot(&DVector::from_column_slice(&b));
            assert_eq!(dot(&a, &b).to_bits(), expected.to_bits(), "length {len}");
        }
        let hidden = |x: usize| std::hint::black_box(x);
        for (n, m, ntst) in SHAPES {
            let (lin, columns, dense, full) = random_system(&mut seed, (n, m, ntst, 2));
            let reduction = CyclicReduction::new(&lin, n);
            let mut columns = columns;
            let nn = columns.nrows();
            for column in columns.as_mut_slice().chunks_exact_mut(nn) {
                reduction.apply_r(column);
            }
            let mut rows = dense.clone();
            let mut sys =
                Bordered::transformed(&reduction, &columns, &mut rows, BorderedStore::default())
                    .unwrap();
            let mut rows_any = dense.clone();
            let mut store = BorderedStore::default();
            let shape = (hidden(n), hidden(m), hidden(2));
            eliminate_dense(&reduction, &columns, &mut rows_any, &mut store, shape).unwrap();
            let bits = |x: &DMatrix<f64>| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&rows), bits(&rows_any), "n {n} m {m} ntst {ntst}");
            for (a, b) in sys.store.interior.iter().zip(&store.interior) {
                assert_eq!(bits(a), bits(b), "n {n} m {m} ntst {ntst}");
            }
            let rhs: Vec<f64> = (0..full.nrows()).map(|_| noise(&mut seed)).collect();
            let (mut z, mut z_any) = (Vec::new(), Vec::new());
            sys.solve_into(&rhs, &mut z).unwrap();
            sys.solve_shaped(&rhs, &mut z_any, shape).unwrap();
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&z), bits(&z_any), "n {n} m {m} ntst {ntst}");
        }
    }

    /// The slice kernels of the dense rows' elimination and of the solve
    /// against the nalgebra operations they replaced, to the bit:
    /// `subtract_products` against `gemm_tr`, `subtract_product` against
    /// `gemv`, `back_substitute` against `solve_upper_triangular_mut`,
    /// `multipliers` against `transpose_to` and
    /// `tr_solve_upper_triangular_mut`; sizes 1 to 12, borders 1 to 4,
    /// entries of very different sizes.
    #[test]
    fn the_slice_kernels_are_nalgebras_operations_to_the_bit() {
        let mut seed = 23;
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let matrix = |seed: &mut u64, rows: usize, cols: usize| {
            DMatrix::from_fn(rows, cols, |i, j| {
                noise(seed) * 10f64.powi(((i + 2 * j) % 5) as i32 * 3 - 6)
            })
        };
        for len in 1..=12 {
            let mut r = matrix(&mut seed, len, len);
            for i in 0..len {
                r[(i, i)] = 2.0 + noise(&mut seed);
            }
            let y0 = matrix(&mut seed, len, 1);
            let mut expected = y0.clone();
            assert!(r.solve_upper_triangular_mut(&mut expected));
            let mut got = y0.as_slice().to_vec();
            assert!(back_substitute(r.as_slice(), &mut got));
            assert_eq!(bits(&got), bits(expected.as_slice()), "back, {len}");
            for k in 1..=4 {
                let (lt, b, out0) = (
                    matrix(&mut seed, len, k),
                    matrix(&mut seed, len, 3),
                    matrix(&mut seed, k, 3),
                );
                let mut expected = out0.clone();
                expected.gemm_tr(-1.0, &lt, &b, 1.0);
                let mut got = out0.clone();
                let columns = |c: usize| &b.as_slice()[c * len..][..len];
                subtract_products(got.as_mut_slice(), k, (lt.as_slice(), len), columns);
                assert_eq!(
                    bits(got.as_slice()),
                    bits(expected.as_slice()),
                    "gemm_tr, {len} {k}"
                );
                let (a, x, w0) = (
                    matrix(&mut seed, len, k),
                    matrix(&mut seed, k, 1),
                    matrix(&mut seed, len, 1),
                );
                let mut expected = DVector::from_column_slice(w0.as_slice());
                expected.gemv(-1.0, &a, &DVector::from_column_slice(x.as_slice()), 1.0);
                let mut got = w0.as_slice().to_vec();
                subtract_product(&mut got, |c| &a.as_slice()[c * len..][..len], x.as_slice());
                assert_eq!(bits(&got), bits(expected.as_slice()), "gemv, {len} {k}");
                let rows = matrix(&mut seed, k, len + 3);
                let mut expected = DMatrix::zeros(len, k);
                rows.columns(2, len).transpose_to(&mut expected);
                assert!(r.tr_solve_upper_triangular_mut(&mut expected));
                let mut got = DMatrix::zeros(0, 0);
                multipliers(rows.as_slice(), k, (2, len), r.as_slice(), &mut got).unwrap();
                assert_eq!(
                    bits(got.as_slice()),
                    bits(expected.as_slice()),
                    "lambda, {len} {k}"
                );
            }
        }
    }

    #[test]
    fn the_reductions_own_border_is_r_applied_to_the_border_columns() {
        let mut seed = 5;
        for (n, m, ntst) in SHAPES {
            let (lin, _, _, _) = random_system(&mut seed, (n, m, ntst, 2));
            let reduction = CyclicReduction::new(&lin, n);
            let mut columns = lin.border_columns();
            let nn = columns.nrows();
            for column in columns.as_mut_slice().chunks_exact_mut(nn) {
                reduction.apply_r(column);
            }
            let scale = columns.amax();
            let difference = (&columns - reduction.border()).amax();
            assert!(
                difference <= 1e-14 * scale,
                "n {n} m {m} ntst {ntst}: {difference:e} of {scale:e}"
            );
        }
    }

    /// The sweep on rows sums each column's dot product with a reflector in
    /// row order in its own lane: the border it transforms is `apply_r`'s,
    /// which reflects one column at a time, to the bit; and the reduction
    /// compiled for AVX2 is the baseline one, and the shapes compiled with
    /// their sizes constant (`n = 2, 3`, degree 4) the code for any size,
    /// entry by entry.
    #[test]
    fn the_sweep_in_lanes_is_the_column_by_column_reflection_to_the_bit() {
        let mut seed = 11;
        for (n, m, ntst) in SHAPES {
            let (lin, _, _, _) = random_system(&mut seed, (n, m, ntst, 2));
            let mut reduction = CyclicReduction::new(&lin, n);
            let mut columns = lin.border_columns();
            let nn = columns.nrows();
            for column in columns.as_mut_slice().chunks_exact_mut(nn) {
                reduction.apply_r(column);
            }
            assert_eq!(&columns, reduction.border(), "n {n} m {m} ntst {ntst}");
            reduction.factor_here(&lin);
            let baseline = reduction.clone();
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2, detected just above.
                unsafe { reduction.factor_avx2(&lin) };
            }
            let mut any_size = reduction.clone();
            let hidden = |x: usize| std::hint::black_box(x);
            any_size.factor_shaped(&lin, hidden(n), hidden(m));
            let parts = |r: &CyclicReduction| {
                let mut all: Vec<f64> = r.border.iter().copied().collect();
                for iv in &r.intervals {
                    all.extend(
                        iv.scale
                            .iter()
                            .chain(&iv.qr.v)
                            .chain(&iv.qr.r)
                            .chain(&iv.top),
                    );
                }
                for el in &r.eliminations {
                    all.extend(el.qr.v.iter().chain(&el.qr.r).chain(&el.x).chain(&el.z));
                }
                for (a, b) in r.a.iter().zip(&r.b) {
                    all.extend(a.iter().chain(b));
                }
                all.into_iter().map(f64::to_bits).collect::<Vec<_>>()
            };
            assert_eq!(
                parts(&baseline),
                parts(&reduction),
                "n {n} m {m} ntst {ntst}"
            );
            assert_eq!(
                parts(&baseline),
                parts(&any_size),
                "n {n} m {m} ntst {ntst}: any size"
            );
        }
    }

    /// [`Householder::factor`] against the QR reflected one column at a
    /// time with [`reflect`] (each dot product summed in row order from
    /// `-0.0`, the arithmetic of the sweep before it ran in lanes; the
    /// reflectors formed by the same [`reflector_of`]), to the bit: the triangular factor, the reflectors and the trailing columns,
    /// on blocks of 1 to 14 rows, 1 to 8 columns and 0 to 22 trailing
    /// columns (one to four passes of up to [`GROUPS`] groups of lanes),
    /// with the scratch holding NaN from before and entries of very
    /// different sizes.
    #[test]
    fn the_sweep_in_lanes_is_the_householder_qr_column_by_column_to_the_bit() {
        let mut seed = 13;
        let mut sweep = Sweep::default();
        let bits = |x: &[f64]| x.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
        for rows in 1..=14 {
            for cols in 1..=rows.min(8) {
                for trailing in [0, 1, 5, 16, 22] {
                    let width = cols + trailing;
                    let a: Vec<f64> = (0..rows * width)
                        .map(|i| noise(&mut seed) * 10f64.powi((i % 7) as i32 * 3 - 9))
                        .collect();
                    // Column-major: column c at a[c rows..].
                    let mut qr = Householder::zeros(rows, cols);
                    sweep.shape(rows, width);
                    sweep.w.fill(f64::NAN);
                    for c in 0..width {
                        for r in 0..rows {
                            sweep.w[r * sweep.width + c] = a[c * rows + r];
                        }
                    }
                    qr.factor(&mut sweep.w, (rows, cols), sweep.width);
                    let mut columns = a.clone();
                    let mut r_factor = vec![0.0; cols * cols];
                    for j in 0..cols {
                        let (left, right) = columns.split_at_mut((j + 1) * rows);
                        let v = &mut left[j * rows + j..];
                        r_factor[j * cols + j] = reflector_of(v);
                        for (c, column) in right.chunks_exact_mut(rows).enumerate() {
                            reflect(v, &mut column[j..]);
                            if j + 1 + c < cols {
                                r_factor[(j + 1 + c) * cols + j] = column[j];
                            }
                        }
                        assert_eq!(
                            bits(qr.reflector(j)),
                            bits(v),
                            "{rows} x {cols} + {trailing}: v_{j}"
                        );
                    }
                    assert_eq!(
                        bits(qr.r.as_slice()),
                        bits(&r_factor),
                        "{rows} x {cols} + {trailing}: r"
                    );
                    for t in 0..trailing {
                        let expected = &columns[(cols + t) * rows..(cols + t + 1) * rows];
                        let got: Vec<f64> = (0..rows)
                            .map(|r| sweep.w[r * sweep.width + cols + t])
                            .collect();
                        assert_eq!(
                            bits(&got),
                            bits(expected),
                            "{rows} x {cols} + {trailing}: column {t}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn bordered_solves_with_the_matrix_and_its_transpose() {
        let mut seed = 11;
        for (n, m, ntst) in SHAPES {
            for k in [1, 2, 3, 4] {
                let (lin, columns, dense, full) = random_system(&mut seed, (n, m, ntst, k));
                let dim = full.nrows();
                let rhs: Vec<f64> = (0..dim).map(|_| noise(&mut seed)).collect();
                let b = DVector::from_column_slice(&rhs);
                let reference = full.clone().full_piv_lu().solve(&b).unwrap();
                let adjoint = full.transpose().full_piv_lu().solve(&b).unwrap();
                let reduction = CyclicReduction::new(&lin, n);
                let (mut columns, mut dense) = (columns, dense);
                let nn = columns.nrows();
                for column in columns.as_mut_slice().chunks_exact_mut(nn) {
                    reduction.apply_r(column);
                }
                let mut sys = Bordered::transformed(
                    &reduction,
                    &columns,
                    &mut dense,
                    BorderedStore::default(),
                )
                .unwrap();
                for (x, reference) in [
                    (sys.solve(&rhs).unwrap(), reference),
                    (sys.solve_transpose(&rhs).unwrap(), adjoint),
                ] {
                    let scale = reference.amax();
                    for (a, b) in x.iter().zip(reference.iter()) {
                        assert!(
                            (a - b).abs() < 1e-12 * scale,
                            "n {n} m {m} ntst {ntst} k {k}: {a} vs {b}"
                        );
                    }
                }
            }
        }
    }
}
