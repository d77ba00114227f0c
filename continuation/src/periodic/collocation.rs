//! The collocation equations of a periodic orbit and their exact, sparse Jacobian.
//!
//! On interval `i` (length `h_i`) with local nodes `u_{i,l}`, at each Gauss
//! point `z_k`:
//!
//! ```text
//! sum_l L_l'(z_k) u_{i,l} - h_i T f( sum_l L_l(z_k) u_{i,l}, p ) = 0
//! ```
//!
//! or, for a field with an implicit form `rho(x, p) x' = g(x, p)`
//! ([`VectorField::implicit_rhs`]), equation `r` multiplied by `rho_r`:
//!
//! ```text
//! rho_r sum_l L_l'(z_k) u_{i,l,r} - h_i T g_r( sum_l L_l(z_k) u_{i,l}, p ) = 0
//! ```
//!
//! (the same orbits and Floquet multipliers; the rounding of `g_r` is not
//! divided by `rho_r`, and `rho_r = 0` leaves the algebraic `g_r = 0`),
//! and the integral phase condition against a reference orbit `u_ref`,
//! `int_0^1 <u(tau), u_ref'(tau)> dtau = 0` (Doedel; Kuznetsov 1998 §10.3).
//! Unknowns `z = (u, T, p_k)`: `N + 2` with `N = NTST m n`; equations `N + 1`.

use super::cycle::Cycle;
use super::mesh::Mesh;
use crate::system::{implicit_first_order, VectorField};
use nalgebra::{DMatrix, DMatrixView};
use rayon::prelude::*;
use smallvec::SmallVec;

/// The collocation system of one mesh, with the phase reference.
pub struct Collocation<'a, S: VectorField> {
    pub sys: &'a S,
    pub mesh: Mesh,
    /// Index of the free parameter.
    pub k: usize,
    /// Parameters (entry `k` is read from the unknowns).
    pub p: Vec<f64>,
    /// `u_ref'(tau)` at the Gauss points, interval-major: `[(i m + k) n ..]`.
    phase_ref: Vec<f64>,
    /// The collocation equations in the field's implicit form
    /// ([`VectorField::implicit_rhs`]), when it has one.
    implicit: bool,
}

/// Residual and Jacobian of the collocation system, by interval.
#[derive(Default)]
pub struct Linearization {
    /// Collocation residuals (interval-major, `N` values), then the phase condition.
    pub residual: Vec<f64>,
    /// The intervals' Jacobian blocks in one slab ([`Blocks`]).
    pub blocks: Blocks,
    /// The phase condition's row on the node values (it involves neither `T` nor `p_k`).
    pub phase: Vec<f64>,
    /// Largest size of the terms of a collocation residual and of its
    /// linearization, `max(|u'| + |h T f|, sum_c |J_rc| |z_c|)`: rounding
    /// leaves residuals of about `eps` times this (large on stiff stretches
    /// of an orbit, where `f` has huge, canceling terms).
    pub term_scale: f64,
    /// `int_0^T tr J(x(t)) dt` by the collocation quadrature: the logarithm
    /// of the product of the Floquet multipliers (Liouville's formula).
    pub trace_integral: f64,
    /// Scratch of [`Collocation::linearize_into`], kept with the storage.
    pub(crate) scratch: LinearizeScratch,
}

/// Scratch of [`Collocation::linearize_into`]: the parameters, each
/// interval's phase-row entries and sums.
#[derive(Clone, Debug, Default)]
pub(crate) struct LinearizeScratch {
    p: Vec<f64>,
    phase_parts: Vec<f64>,
    parts: Vec<IntervalSums>,
    /// The Jacobian of `f` at a collocation point (and the derivatives of
    /// an implicit form), when the intervals run in turn.
    jac: PointScratch,
}

/// Scratch of one collocation point, one per thread: the Jacobian `n x n`
/// of the collocation row (`D_x f`, or of an implicit form's row divided by
/// `-h T`), and an implicit form's `drho`, `dg` (`n x (n + 1)`,
/// [`implicit_first_order`]; empty for the explicit form).
type PointScratch = (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>);

/// The Jacobian blocks of the collocation rows, one per interval, in one
/// contiguous slab: interval `i`'s block (its `m n` rows on its `m + 1`
/// nodes, `n` columns each, then on `T` and `p_k`) is column-major at
/// `data[i rows cols..(i + 1) rows cols]`.
#[derive(Clone, Debug, Default)]
pub struct Blocks {
    data: Vec<f64>,
    rows: usize,
    cols: usize,
}

impl Blocks {
    /// `count` blocks of `rows x cols`, zero.
    pub fn zeros(count: usize, (rows, cols): (usize, usize)) -> Self {
        Blocks {
            data: vec![0.0; count * rows * cols],
            rows,
            cols,
        }
    }

    /// Makes it `count` blocks of `rows x cols` (keeps the storage and its
    /// values when the shape is already that).
    fn reshape(&mut self, count: usize, (rows, cols): (usize, usize)) {
        if (self.rows, self.cols) != (rows, cols) || self.data.len() != count * rows * cols {
            *self = Blocks::zeros(count, (rows, cols));
        }
    }

    /// Number of blocks (intervals).
    pub fn count(&self) -> usize {
        self.data
            .len()
            .checked_div(self.rows * self.cols)
            .unwrap_or(0)
    }

    /// The shape `(rows, cols)` of every block.
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Block `i`, column-major.
    pub fn slice(&self, i: usize) -> &[f64] {
        let size = self.rows * self.cols;
        &self.data[i * size..(i + 1) * size]
    }

    /// Block `i` as a matrix view.
    pub fn block(&self, i: usize) -> DMatrixView<'_, f64> {
        DMatrixView::from_slice(self.slice(i), self.rows, self.cols)
    }

    /// The blocks in order, column-major.
    pub fn slices(&self) -> std::slice::ChunksExact<'_, f64> {
        self.data.chunks_exact((self.rows * self.cols).max(1))
    }

    /// The blocks from matrices of one shape.
    #[cfg(test)]
    pub fn from_matrices(blocks: &[DMatrix<f64>]) -> Self {
        let (rows, cols) = blocks.first().map_or((0, 0), |b| b.shape());
        Blocks {
            data: blocks.iter().flat_map(|b| b.iter().copied()).collect(),
            rows,
            cols,
        }
    }
}

impl Linearization {
    /// The border columns `dF/dT`, `dF/dp_k` of the collocation rows
    /// (interval-major, `N x 2`).
    pub fn border_columns(&self) -> DMatrix<f64> {
        let (mn, cols) = self.blocks.shape();
        let nodes = cols - 2;
        let mut columns = DMatrix::zeros(self.blocks.count() * mn, 2);
        for i in 0..self.blocks.count() {
            columns
                .rows_mut(i * mn, mn)
                .copy_from(&self.blocks.block(i).columns(nodes, 2));
        }
        columns
    }
}

impl<'a, S: VectorField> Collocation<'a, S> {
    /// The system on `reference`'s mesh, with `reference` as the phase reference.
    pub fn new(sys: &'a S, reference: &Cycle, k: usize) -> Self {
        let mesh = reference.mesh.clone();
        let n = reference.n;
        let m = mesh.degree;
        let mut phase_ref = Vec::with_capacity(mesh.ntst() * m * n);
        for i in 0..mesh.ntst() {
            let h = mesh.t[i + 1] - mesh.t[i];
            let nodes: SmallVec<[&[f64]; 8]> =
                (0..=m).map(|l| reference.node(mesh.node(i, l))).collect();
            for kk in 0..m {
                for j in 0..n {
                    let d: f64 = (0..=m).map(|l| mesh.dbasis[kk][l] * nodes[l][j]).sum();
                    phase_ref.push(d / h);
                }
            }
        }
        Collocation {
            sys,
            mesh,
            k,
            p: reference.p.clone(),
            phase_ref,
            implicit: sys.has_implicit_form(),
        }
    }

    /// The same system with the collocation equations in the explicit form
    /// `x' = f(x, p)` (the form the second derivatives of the fold-of-cycles
    /// system differentiate).
    pub fn explicit(self) -> Self {
        Collocation {
            implicit: false,
            ..self
        }
    }

    /// The orbit described by unknowns `z`.
    pub fn cycle(&self, z: &[f64]) -> Cycle {
        let nn = self.mesh.n_nodes() * self.sys.dim();
        let mut p = self.p.clone();
        p[self.k] = z[nn + 1];
        Cycle {
            mesh: self.mesh.clone(),
            u: z[..nn].to_vec(),
            period: z[nn],
            p,
            n: self.sys.dim(),
        }
    }

    /// Unknowns of an orbit on this mesh.
    pub fn unknowns(&self, c: &Cycle) -> Vec<f64> {
        let mut z = c.u.clone();
        z.push(c.period);
        z.push(c.p[self.k]);
        z
    }

    /// Residual and Jacobian at `z`. The intervals are independent and are
    /// linearized in parallel (rayon) on meshes of at least
    /// [`PARALLEL_INTERVALS`] intervals.
    pub fn linearize(&self, z: &[f64]) -> Linearization {
        let mut lin = Linearization::default();
        self.linearize_into(z, &mut lin);
        lin
    }

    /// [`Collocation::linearize`] into `lin`, reusing its storage when it
    /// has this mesh's shape (Newton's iterations on one mesh allocate
    /// nothing per interval).
    pub fn linearize_into(&self, z: &[f64], lin: &mut Linearization) {
        match (self.sys.dim(), self.mesh.degree) {
            (2, 4) => self.linearize_shaped::<2, 4>(z, lin),
            (3, 4) => self.linearize_shaped::<3, 4>(z, lin),
            (2, _) => self.linearize_shaped::<2, 0>(z, lin),
            (3, _) => self.linearize_shaped::<3, 0>(z, lin),
            _ => self.linearize_shaped::<0, 0>(z, lin),
        }
    }

    /// [`Collocation::linearize_into`]; `N` and `M` as in
    /// [`Collocation::interval`].
    pub(super) fn linearize_shaped<const N: usize, const M: usize>(
        &self,
        z: &[f64],
        lin: &mut Linearization,
    ) {
        let n = self.sys.dim();
        let m = self.mesh.degree;
        debug_assert!(
            (N == 0 || N == n) && (M == 0 || M == m),
            "shape ({N}, {M}) for ({n}, {m})"
        );
        let (mn, ncols) = (m * n, (m + 1) * n + 2);
        let nn = self.mesh.n_nodes() * n;
        let ntst = self.mesh.ntst();
        let mut scratch = std::mem::take(&mut lin.scratch);
        let p = &mut scratch.p;
        p.clear();
        p.extend_from_slice(&self.p);
        p[self.k] = z[nn + 1];
        let p = &*p;
        lin.blocks.reshape(ntst, (mn, ncols));
        lin.residual.resize(nn + 1, 0.0);
        // Each interval's phase-row entries on its m + 1 nodes (neighbours
        // share a node), added up after.
        let phase_parts = &mut scratch.phase_parts;
        phase_parts.clear();
        phase_parts.resize(ntst * (m + 1) * n, 0.0);
        // The Jacobian of `f` at a collocation point: one per thread.
        let implicit_columns = if self.implicit { n + 1 } else { 0 };
        let jacobian = || {
            (
                DMatrix::zeros(n, n),
                DMatrix::zeros(n, implicit_columns),
                DMatrix::zeros(n, implicit_columns),
            )
        };
        let sums = |jac: &mut PointScratch, (i, ((block, residual), phase)): (usize, Zipped)| {
            let out = (block, residual, phase);
            self.interval::<N, M>(i, z, p, out, jac)
        };
        // Each interval's sums, then added up in order (the same totals
        // whether or not the intervals ran in parallel).
        let parts = &mut scratch.parts;
        parts.clear();
        if ntst >= PARALLEL_INTERVALS {
            lin.blocks
                .data
                .par_chunks_exact_mut(mn * ncols)
                .zip(lin.residual[..nn].par_chunks_exact_mut(mn))
                .zip(phase_parts.par_chunks_exact_mut((m + 1) * n))
                .enumerate()
                .with_min_len(PARALLEL_INTERVALS / 2)
                .map_init(jacobian, sums)
                .collect_into_vec(parts);
        } else {
            let jac = &mut scratch.jac;
            if jac.0.shape() != (n, n) || jac.1.shape() != (n, implicit_columns) {
                *jac = jacobian();
            }
            parts.extend(
                lin.blocks
                    .data
                    .chunks_exact_mut(mn * ncols)
                    .zip(lin.residual[..nn].chunks_exact_mut(mn))
                    .zip(phase_parts.chunks_exact_mut((m + 1) * n))
                    .enumerate()
                    .map(|item| sums(jac, item)),
            );
        }
        let total = parts
            .iter()
            .fold(IntervalSums::default(), |a, b| IntervalSums {
                term_scale: a.term_scale.max(b.term_scale),
                trace_integral: a.trace_integral + b.trace_integral,
                phase_residual: a.phase_residual + b.phase_residual,
            });
        lin.phase.clear();
        lin.phase.resize(nn, 0.0);
        for (i, part) in phase_parts.chunks_exact((m + 1) * n).enumerate() {
            for l in 0..=m {
                let col0 = self.mesh.node(i, l) * n;
                for j in 0..n {
                    lin.phase[col0 + j] += part[l * n + j];
                }
            }
        }
        lin.residual[nn] = total.phase_residual;
        lin.term_scale = total.term_scale;
        lin.trace_integral = total.trace_integral;
        lin.scratch = scratch;
    }

    /// The state `x` and its derivative `dx` in the local variable (`h T`
    /// times the time derivative) at collocation point `kk` of interval `i`
    /// of the orbit `z` (`n` entries each, overwritten).
    /// `N` and `M` as in [`Collocation::interval`].
    #[inline(always)]
    fn point_state<const N: usize, const M: usize>(
        &self,
        i: usize,
        kk: usize,
        z: &[f64],
        x: &mut [f64],
        dx: &mut [f64],
    ) {
        let n = if N == 0 { x.len() } else { N };
        let m = if M == 0 { self.mesh.degree } else { M };
        let node = |g: usize| &z[g * n..(g + 1) * n];
        // Relative to the interval's first node (the basis sums to 1,
        // its derivatives to 0): the derivative is then rounded
        // relative to the change across the interval, not to the
        // values themselves. Each component is summed over the nodes in
        // their order in locals and written once: with the sums run node by
        // node in place, the release binary built with fat LTO and one
        // codegen unit (rustc 1.95.0) was seen to return the first
        // component's derivative as 0, the cause not established
        // (docs/performance.md, 2026-11-27, fifth session).
        let v0 = node(self.mesh.node(i, 0));
        let (basis, dbasis) = (&self.mesh.basis[kk], &self.mesh.dbasis[kk]);
        for j in 0..n {
            let (mut xj, mut dxj) = (0.0, 0.0);
            for l in 1..=m {
                let d = node(self.mesh.node(i, l))[j] - v0[j];
                xj += basis[l] * d;
                dxj += dbasis[l] * d;
            }
            x[j] = xj + v0[j];
            dx[j] = dxj;
        }
    }

    /// The residual of the collocation system at `z` alone (no
    /// derivatives: `f`, or the implicit form's `rho` and `g`, in `f64`),
    /// into `out` (`N + 1` entries: the collocation residuals, then the
    /// phase condition), the same values as [`Collocation::linearize_into`]
    /// writes, summed in the same order.
    pub fn residual_into(&self, z: &[f64], out: &mut Vec<f64>) {
        match (self.sys.dim(), self.mesh.degree) {
            (2, 4) => self.residual_shaped::<2, 4>(z, out),
            (3, 4) => self.residual_shaped::<3, 4>(z, out),
            _ => self.residual_shaped::<0, 0>(z, out),
        }
    }

    /// [`Collocation::residual_into`]; `N` and `M` as in
    /// [`Collocation::interval`].
    pub(super) fn residual_shaped<const N: usize, const M: usize>(
        &self,
        z: &[f64],
        out: &mut Vec<f64>,
    ) {
        debug_assert!(
            (N == 0 || N == self.sys.dim()) && (M == 0 || M == self.mesh.degree),
            "shape ({N}, {M})"
        );
        let n = if N == 0 { self.sys.dim() } else { N };
        let m = if M == 0 { self.mesh.degree } else { M };
        let nn = self.mesh.n_nodes() * n;
        let period = z[nn];
        let mut p: SmallVec<[f64; 16]> = SmallVec::from_slice(&self.p);
        p[self.k] = z[nn + 1];
        out.clear();
        out.resize(nn + 1, 0.0);
        let mut scratch = SmallVec::<[f64; 64]>::from_elem(0.0, 4 * n);
        let (x, rest) = scratch.split_at_mut(n);
        let (dx, rest) = rest.split_at_mut(n);
        let (f, rho) = rest.split_at_mut(n);
        let mut phase_residual = 0.0;
        for (i, residual) in out[..nn].chunks_exact_mut(m * n).enumerate() {
            let h = self.mesh.t[i + 1] - self.mesh.t[i];
            let mut interval_phase = 0.0;
            for kk in 0..m {
                self.point_state::<N, M>(i, kk, z, x, dx);
                if self.implicit {
                    self.sys.implicit_rhs(x, &p, rho, f);
                } else {
                    rho.fill(1.0);
                    self.sys.rhs(x, &p, f);
                }
                for j in 0..n {
                    residual[kk * n + j] = rho[j] * dx[j] - h * period * f[j];
                }
                let w = h * self.mesh.weights[kk];
                let dref = &self.phase_ref[(i * m + kk) * n..(i * m + kk + 1) * n];
                for j in 0..n {
                    interval_phase += w * x[j] * dref[j];
                }
            }
            phase_residual += interval_phase;
        }
        out[nn] = phase_residual;
    }

    /// The collocation equations of interval `i` at `z` (parameters `p`),
    /// linearized into `out`: its block, its `m n` residuals and its
    /// phase-row entries on its `m + 1` nodes; returns its terms of the
    /// phase residual, the term scale and the trace integral. `jac` is
    /// scratch for the Jacobian of `f` at each collocation point (and the
    /// derivatives of the implicit form). `N` and `M` are the state
    /// dimension and the degree when known at compile time (the inner loops
    /// unrolled), `0` otherwise; the arithmetic is the same.
    fn interval<const N: usize, const M: usize>(
        &self,
        i: usize,
        z: &[f64],
        p: &[f64],
        out: IntervalOut,
        (jac, drho, dg): &mut PointScratch,
    ) -> IntervalSums {
        let (block, residual, phase) = out;
        let n = if N == 0 { self.sys.dim() } else { N };
        let m = if M == 0 { self.mesh.degree } else { M };
        let mn = m * n;
        let nn = self.mesh.n_nodes() * n;
        let period = z[nn];
        let node = |g: usize| &z[g * n..(g + 1) * n];
        let h = self.mesh.t[i + 1] - self.mesh.t[i];
        let mut sums = IntervalSums::default();
        phase.fill(0.0);
        // Zeroed for every interval, as a new matrix would be.
        jac.fill(0.0);
        // Scratch of `n` entries each: the state and its derivative at the
        // point, the row sums of the term scale, `f` (`g`) and `df/dp_k`, and
        // the scales `rho` of the equations (1 in the explicit form).
        let mut scratch = SmallVec::<[f64; 64]>::from_elem(0.0, 6 * n);
        let (x, rest) = scratch.split_at_mut(n);
        let (dx, rest) = rest.split_at_mut(n);
        let (row_sums, rest) = rest.split_at_mut(n);
        let (f, rest) = rest.split_at_mut(n);
        let (fp, rho) = rest.split_at_mut(n);
        rho.fill(1.0);
        // Column-major: entry (r, c) of the block at `c mn + r`.
        for kk in 0..m {
            let row0 = kk * n;
            row_sums.fill(0.0);
            self.point_state::<N, M>(i, kk, z, x, dx);
            if self.implicit {
                // Row r, `rho_r x'_r - g_r` times `h T` (`x'_r = dx_r / (h T)`):
                // its derivatives along `x_c` and `p_k`, divided by `-h T`,
                // take the places of `D_x f` and `df/dp_k` (`f` is `g`).
                implicit_first_order(self.sys, x, p, self.k, (rho, f, drho, dg));
                // Column-major, entry (r, c) at `c n + r`.
                let (js, dgs, drs) = (
                    &mut jac.as_mut_slice()[..n * n],
                    &dg.as_slice()[..n * (n + 1)],
                    &drho.as_slice()[..n * (n + 1)],
                );
                for r in 0..n {
                    let slope = dx[r] / (h * period);
                    for c in 0..n {
                        js[c * n + r] = dgs[c * n + r] - drs[c * n + r] * slope;
                    }
                    fp[r] = dgs[n * n + r] - drs[n * n + r] * slope;
                }
            } else {
                self.sys.first_order(x, p, self.k, (f, jac, fp));
            }
            for j in 0..n {
                residual[row0 + j] = rho[j] * dx[j] - h * period * f[j];
                sums.term_scale = sums
                    .term_scale
                    .max((rho[j] * dx[j]).abs() + (h * period * f[j]).abs());
                block[(m + 1) * n * mn + row0 + j] = -h * f[j];
                block[((m + 1) * n + 1) * mn + row0 + j] = -h * period * fp[j];
            }
            // Column-major like the block: `D_x f` (r, c) at `c n + r`.
            let js = jac.as_slice();
            for l in 0..=m {
                let (b, db) = (self.mesh.basis[kk][l], self.mesh.dbasis[kk][l]);
                let v = node(self.mesh.node(i, l));
                let hpb = h * period * b;
                for (r, row_sum) in row_sums.iter_mut().enumerate() {
                    for c in 0..n {
                        let entry = if r == c { rho[r] * db } else { 0.0 } - hpb * js[c * n + r];
                        block[(l * n + c) * mn + row0 + r] = entry;
                        *row_sum += entry.abs() * v[c].abs();
                    }
                }
            }
            sums.term_scale = row_sums.iter().fold(sums.term_scale, |a, v| a.max(*v));
            let w = h * self.mesh.weights[kk];
            // `tr D_x f`, in the implicit form `sum_r J_rr / rho_r` (exact at
            // a solution, where `x'_r = g_r / rho_r`).
            sums.trace_integral += w * period * (0..n).map(|j| js[j * n + j] / rho[j]).sum::<f64>();
            let dref = &self.phase_ref[(i * m + kk) * n..(i * m + kk + 1) * n];
            for j in 0..n {
                sums.phase_residual += w * x[j] * dref[j];
            }
            for (l, row) in phase.chunks_exact_mut(n).enumerate() {
                let wb = w * self.mesh.basis[kk][l];
                for (entry, d) in row.iter_mut().zip(dref) {
                    *entry += wb * d;
                }
            }
        }
        sums
    }
}

/// Where [`Collocation::interval`] writes: the interval's block, its
/// residuals and its phase-row entries.
type IntervalOut<'o> = (&'o mut [f64], &'o mut [f64], &'o mut [f64]);

/// [`IntervalOut`] as the iterators zip it.
type Zipped<'o> = ((&'o mut [f64], &'o mut [f64]), &'o mut [f64]);

/// One interval's terms of the phase residual, the term scale (a maximum)
/// and the trace integral; also their totals over the mesh.
#[derive(Clone, Copy, Debug, Default)]
struct IntervalSums {
    term_scale: f64,
    trace_integral: f64,
    phase_residual: f64,
}

/// Meshes of at least this many intervals are linearized in parallel: below,
/// an interval's work (a few microseconds) does not pay for the threads.
pub const PARALLEL_INTERVALS: usize = 64;
