//! Structured solution of the linearized collocation system: condensation of
//! the interior nodes interval by interval, then orthogonal cyclic reduction
//! of the mesh nodes, with the dense rows (phase condition, arclength or
//! fixed-parameter condition) carried through every elimination — the
//! strategy of AUTO's collocation solver (Doedel, Keller & Kernévez 1991,
//! "Numerical analysis and control of bifurcation problems (II)", §5), here
//! with Householder QR at every step instead of Gaussian elimination.
//!
//! Every relation is kept homogeneous: the right-hand side is one more column
//! multiplying the constant 1, so `A y_left + B y_right + E [x; 1] = 0` with
//! `x` the border unknowns (period, parameter). The Floquet pencil is the
//! special case without border columns (see [`super::floquet`]).
//!
//! Cost: `O(NTST (m n)^3)` flops in small dense blocks, no fill-in, no
//! symbolic analysis; the same reduction yields the Floquet multipliers.

use crate::error::ContinuationError;
use nalgebra::DMatrix;

/// `a y_left + b y_right + e [x; 1] = 0`: `n` equations relating two mesh
/// nodes (consecutive ones after condensation; farther apart after reduction).
#[derive(Clone, Debug)]
pub struct Relation {
    pub left: usize,
    pub right: usize,
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub e: DMatrix<f64>,
}

/// `r y_node + x y_left + z y_right + w [x; 1] = 0` with `r` upper
/// triangular: how an eliminated node is recovered.
struct Elimination {
    node: usize,
    left: usize,
    right: usize,
    r: DMatrix<f64>,
    x: DMatrix<f64>,
    z: DMatrix<f64>,
    w: DMatrix<f64>,
}

/// Dense rows (`k` of them) as they are carried through the eliminations:
/// `sum_j y[j] y_j + e [x; 1] = 0`, `y[j]` of size `k x n`.
pub struct DenseRows {
    pub y: Vec<DMatrix<f64>>,
    pub e: DMatrix<f64>,
}

impl DenseRows {
    /// Substitutes the eliminated node `el.node` into the rows:
    /// `y_node = -r^{-1} (x y_left + z y_right + w [x; 1])`.
    fn substitute(&mut self, el: &Elimination) -> Result<(), ContinuationError> {
        let d = std::mem::replace(&mut self.y[el.node], DMatrix::zeros(0, 0));
        // lambda = d r^{-1}, from r^T lambda^T = d^T.
        let lambda =
            el.r.transpose()
                .solve_lower_triangular(&d.transpose())
                .ok_or(ContinuationError::Singular)?
                .transpose();
        self.y[el.left] -= &lambda * &el.x;
        self.y[el.right] -= &lambda * &el.z;
        self.e -= &lambda * &el.w;
        self.y[el.node] = DMatrix::zeros(d.nrows(), d.ncols());
        Ok(())
    }
}

/// QR of the columns `pivot` of `block`, applied to the other columns:
/// returns `(r, top, bottom)` where `top` (as many rows as `pivot` has
/// columns) still involves the pivot unknowns through `r` and `bottom` is
/// free of them.
fn split(
    pivot: DMatrix<f64>,
    mut rest: DMatrix<f64>,
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let k = pivot.ncols();
    let qr = pivot.qr();
    qr.q_tr_mul(&mut rest);
    let r = qr.r();
    let bottom = rest.rows(k, rest.nrows() - k).into_owned();
    let top = rest.rows(0, k).into_owned();
    (r, top, bottom)
}

/// The interior unknowns of one interval, condensed out: its local matrix
/// (`m n` rows; columns: the `m + 1` nodes, then the border and right-hand
/// side columns) becomes a [`Relation`] between its end nodes plus the
/// rows that recover the interior. `i` is the interval, `nodes` the number
/// of mesh nodes (the last interval ends on node 0).
pub struct Condensed {
    pub relation: Relation,
    /// `r w + top [y_i; y_{i+1}; x; 1] = 0` for the interior `w`.
    r: DMatrix<f64>,
    top: DMatrix<f64>,
}

/// Condenses interval `i` (of `nodes` mesh nodes): `local` holds its
/// `m n` rows on the `m + 1` nodes' columns, `border` the same rows on the
/// border columns (and the right-hand side column, if any).
pub fn condense(
    local: nalgebra::DMatrixView<f64>,
    border: &DMatrix<f64>,
    n: usize,
    i: usize,
    nodes: usize,
) -> Condensed {
    let m = local.ncols() / n - 1;
    let ne = border.ncols();
    let mut ends = DMatrix::zeros(local.nrows(), 2 * n + ne);
    ends.columns_mut(0, n).copy_from(&local.columns(0, n));
    ends.columns_mut(n, n).copy_from(&local.columns(m * n, n));
    ends.columns_mut(2 * n, ne).copy_from(border);
    let mut interior = local.columns(n, (m - 1) * n).into_owned();
    // Row equilibration: on stiff stretches of an orbit one component's rows
    // carry entries like h T A/(m v) ~ 1e12 next to O(1) ones, and Householder
    // reflections mixing them would lose the small ones. Scaling an equation
    // changes neither the solution nor the Floquet multipliers.
    for row in 0..local.nrows() {
        let size = local.row(row).iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if size > 0.0 && size.is_finite() {
            ends.row_mut(row).scale_mut(1.0 / size);
            interior.row_mut(row).scale_mut(1.0 / size);
        }
    }
    let (r, top, bottom) = if m > 1 {
        split(interior, ends)
    } else {
        (DMatrix::zeros(0, 0), DMatrix::zeros(0, ends.ncols()), ends)
    };
    Condensed {
        relation: Relation {
            left: i,
            right: (i + 1) % nodes,
            a: bottom.columns(0, n).into_owned(),
            b: bottom.columns(n, n).into_owned(),
            e: bottom.columns(2 * n, ne).into_owned(),
        },
        r,
        top,
    }
}

/// Dense rows given on every node value (`ntst m n` columns, node-major),
/// then on the border unknowns and minus their right-hand side, with the
/// interior nodes of every interval eliminated through its condensation.
pub fn dense_rows(
    rows: &DMatrix<f64>,
    condensed: &[Condensed],
    n: usize,
    m: usize,
) -> Result<DenseRows, ContinuationError> {
    let ntst = condensed.len();
    let k = rows.nrows();
    let nn = ntst * m * n;
    let ne = rows.ncols() - nn;
    let mut d = DenseRows {
        y: (0..ntst)
            .map(|i| rows.columns(i * m * n, n).into_owned())
            .collect(),
        e: rows.columns(nn, ne).into_owned(),
    };
    if m > 1 {
        for (i, c) in condensed.iter().enumerate() {
            let interior = rows.columns(i * m * n + n, (m - 1) * n);
            // lambda = d_w r^{-1}; d_w w = -lambda top [y_i; y_{i+1}; x; 1].
            let lambda =
                c.r.transpose()
                    .solve_lower_triangular(&interior.transpose())
                    .ok_or(ContinuationError::Singular)?
                    .transpose();
            let update = &lambda * &c.top;
            d.y[i] -= update.columns(0, n);
            d.y[(i + 1) % ntst] -= update.columns(n, n);
            d.e -= update.columns(2 * n, ne);
        }
    }
    debug_assert_eq!(d.e.nrows(), k);
    Ok(d)
}

/// Eliminates the node shared by `first` (its right) and `second` (its left).
fn combine(first: &Relation, second: &Relation) -> (Relation, Elimination) {
    let n = first.a.nrows();
    let ne = first.e.ncols();
    let mut pivot = DMatrix::zeros(2 * n, n);
    pivot.rows_mut(0, n).copy_from(&first.b);
    pivot.rows_mut(n, n).copy_from(&second.a);
    let mut rest = DMatrix::zeros(2 * n, 2 * n + ne);
    rest.view_mut((0, 0), (n, n)).copy_from(&first.a);
    rest.view_mut((n, n), (n, n)).copy_from(&second.b);
    rest.view_mut((0, 2 * n), (n, ne)).copy_from(&first.e);
    rest.view_mut((n, 2 * n), (n, ne)).copy_from(&second.e);
    let (r, top, bottom) = split(pivot, rest);
    let relation = Relation {
        left: first.left,
        right: second.right,
        a: bottom.columns(0, n).into_owned(),
        b: bottom.columns(n, n).into_owned(),
        e: bottom.columns(2 * n, ne).into_owned(),
    };
    let elimination = Elimination {
        node: first.right,
        left: first.left,
        right: second.right,
        r,
        x: top.columns(0, n).into_owned(),
        z: top.columns(n, n).into_owned(),
        w: top.columns(2 * n, ne).into_owned(),
    };
    (relation, elimination)
}

/// Orthogonal cyclic reduction of a closed chain of relations down to one
/// relation of node 0 with itself; `dense` rows (if any) follow every
/// elimination. Returns the final relation and the eliminations in order.
fn reduce(
    mut chain: Vec<Relation>,
    mut dense: Option<&mut DenseRows>,
) -> Result<(Relation, Vec<Elimination>), ContinuationError> {
    let mut eliminations = Vec::with_capacity(chain.len());
    while chain.len() > 1 {
        let mut next = Vec::with_capacity(chain.len().div_ceil(2));
        let mut pairs = chain.into_iter();
        while let Some(first) = pairs.next() {
            match pairs.next() {
                Some(second) => {
                    let (relation, el) = combine(&first, &second);
                    if let Some(d) = dense.as_deref_mut() {
                        d.substitute(&el)?;
                    }
                    eliminations.push(el);
                    next.push(relation);
                }
                None => next.push(first),
            }
        }
        chain = next;
    }
    let last = chain.pop().ok_or(ContinuationError::Singular)?;
    Ok((last, eliminations))
}

/// The closed chain reduced to `a y_0 + b y_N = 0` (no border columns):
/// the Floquet pencil `a y = mu (-b) y`.
pub fn reduce_pencil(
    chain: Vec<Relation>,
) -> Result<(DMatrix<f64>, DMatrix<f64>), ContinuationError> {
    let (last, _) = reduce(chain, None)?;
    Ok((last.a, last.b))
}

/// Solves the bordered collocation system from its condensed intervals
/// (border columns `[x | -rhs]`) and its `nx` dense rows (from
/// [`dense_rows`]). Returns the node values (node-major, `ntst m n`)
/// followed by the `nx` border unknowns.
pub fn solve(
    condensed: Vec<Condensed>,
    mut dense: DenseRows,
    n: usize,
    m: usize,
) -> Result<Vec<f64>, ContinuationError> {
    let ntst = condensed.len();
    let ne = dense.e.ncols();
    let nx = ne.saturating_sub(1);
    if ne == 0 || dense.e.nrows() != nx {
        return Err(ContinuationError::Sparse(format!(
            "{} dense rows for {nx} border unknowns",
            dense.e.nrows()
        )));
    }
    let (interiors, chain): (Vec<_>, Vec<_>) = condensed
        .into_iter()
        .map(|c| ((c.r, c.top), c.relation))
        .unzip();
    let (last, eliminations) = reduce(chain, Some(&mut dense))?;
    // Final system in (y_0, x): [a + b, e_x; d_0, d_x] [y_0; x] = -[e_1; d_1].
    let dim = n + nx;
    let mut f = DMatrix::zeros(dim, dim);
    f.view_mut((0, 0), (n, n)).copy_from(&(&last.a + &last.b));
    f.view_mut((0, n), (n, nx))
        .copy_from(&last.e.columns(0, nx));
    f.view_mut((n, 0), (nx, n)).copy_from(&dense.y[0]);
    f.view_mut((n, n), (nx, nx))
        .copy_from(&dense.e.columns(0, nx));
    let mut g = nalgebra::DVector::zeros(dim);
    g.rows_mut(0, n).copy_from(&(-last.e.column(nx)));
    g.rows_mut(n, nx).copy_from(&(-dense.e.column(nx)));
    let sol = f
        .full_piv_lu()
        .solve(&g)
        .ok_or(ContinuationError::Singular)?;
    let mut aug = nalgebra::DVector::from_element(nx + 1, 1.0);
    aug.rows_mut(0, nx).copy_from(&sol.rows(n, nx));
    let mut y = vec![nalgebra::DVector::zeros(n); ntst];
    y[0] = sol.rows(0, n).into_owned();
    for el in eliminations.iter().rev() {
        let rhs = -(&el.x * &y[el.left] + &el.z * &y[el.right] + &el.w * &aug);
        y[el.node] =
            el.r.solve_upper_triangular(&rhs)
                .ok_or(ContinuationError::Singular)?;
    }
    let mut out = vec![0.0; ntst * m * n + nx];
    for (i, (r, top)) in interiors.iter().enumerate() {
        out[i * m * n..i * m * n + n].copy_from_slice(y[i].as_slice());
        if m > 1 {
            let mut ends = nalgebra::DVector::zeros(2 * n + ne);
            ends.rows_mut(0, n).copy_from(&y[i]);
            ends.rows_mut(n, n).copy_from(&y[(i + 1) % ntst]);
            ends.rows_mut(2 * n, ne).copy_from(&aug);
            let w = r
                .solve_upper_triangular(&(-(top * ends)))
                .ok_or(ContinuationError::Singular)?;
            out[i * m * n + n..(i + 1) * m * n].copy_from_slice(w.as_slice());
        }
    }
    out[ntst * m * n..].copy_from_slice(aug.rows(0, nx).as_slice());
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(ContinuationError::Singular)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::periodic::collocation::Linearization;
    use crate::periodic::newton::solve_bordered;

    /// A small deterministic pseudo-random sequence in (-1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn condensed_cyclic_solve_matches_a_dense_solve() {
        let mut seed = 7;
        for (n, m, ntst) in [(2, 1, 2), (3, 4, 5), (2, 3, 8), (3, 2, 7)] {
            let mn = m * n;
            let nn = ntst * mn;
            let dim = nn + 2;
            // Interval blocks: `m n` rows on the `m + 1` nodes and 2 border columns.
            let locals: Vec<DMatrix<f64>> = (0..ntst)
                .map(|_| {
                    DMatrix::from_fn(mn, (m + 1) * n + 2, |r, c| {
                        // Diagonally weighted so the assembled matrix is well conditioned.
                        let d = if c == r + n / 2 { 4.0 } else { 0.0 };
                        d + noise(&mut seed)
                    })
                })
                .collect();
            // Dense rows: the phase condition (nodes only) and an arbitrary row.
            let mut dense = DMatrix::from_fn(2, dim, |_, _| noise(&mut seed));
            dense[(0, nn)] = 0.0;
            dense[(0, nn + 1)] = 0.0;
            let rhs: Vec<f64> = (0..dim).map(|_| noise(&mut seed)).collect();
            // The assembled system.
            let mut full = DMatrix::zeros(dim, dim);
            for (i, b) in locals.iter().enumerate() {
                for r in 0..mn {
                    for l in 0..=m {
                        let node = (i * m + l) % (ntst * m);
                        for c in 0..n {
                            full[(i * mn + r, node * n + c)] += b[(r, l * n + c)];
                        }
                    }
                    full[(i * mn + r, nn)] = b[(r, (m + 1) * n)];
                    full[(i * mn + r, nn + 1)] = b[(r, (m + 1) * n + 1)];
                }
            }
            full.rows_mut(nn, 2).copy_from(&dense);
            let reference = full
                .clone()
                .full_piv_lu()
                .solve(&nalgebra::DVector::from_column_slice(&rhs))
                .unwrap();
            // The structured solve, as Newton's method calls it.
            let lin = Linearization {
                residual: Vec::new(),
                local: locals,
                phase: dense.row(0).columns(0, nn).iter().copied().collect(),
                term_scale: 0.0,
                trace_integral: 0.0,
            };
            let extra: Vec<f64> = dense.row(1).iter().copied().collect();
            let x = solve_bordered(&lin, n, &extra, &rhs).unwrap();
            let scale = reference.amax();
            for (a, b) in x.iter().zip(reference.iter()) {
                assert!(
                    (a - b).abs() < 1e-12 * scale,
                    "n {n} m {m} ntst {ntst}: {a} vs {b}"
                );
            }
        }
    }
}
