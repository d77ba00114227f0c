//! A periodic orbit on a collocation mesh: node values, period, parameters.

use super::mesh::{lagrange_into, lagrange_values, Mesh};
use crate::system::VectorField;
use nalgebra::{DMatrix, DVector, Dyn};
use std::cell::RefCell;

/// A periodic orbit `x(t)`, `t` in `[0, T]`, as piecewise polynomials on a
/// [`Mesh`] of normalized time `tau = t / T`.
#[derive(Clone, Debug)]
pub struct Cycle {
    /// The mesh.
    pub mesh: Mesh,
    /// Node values, node-major: node `g` occupies `u[g n .. (g + 1) n]`.
    pub u: Vec<f64>,
    /// Period `T`.
    pub period: f64,
    /// Full parameter vector.
    pub p: Vec<f64>,
    /// State dimension.
    pub n: usize,
}

impl Cycle {
    /// Node value `g` (periodic index).
    pub fn node(&self, g: usize) -> &[f64] {
        let g = g % self.mesh.n_nodes();
        &self.u[g * self.n..(g + 1) * self.n]
    }

    /// The state at normalized time `tau` in `[0, 1]`.
    pub fn state_at(&self, tau: f64) -> Vec<f64> {
        let mut x = vec![0.0; self.n];
        self.state_into(tau, &mut x);
        x
    }

    /// [`Cycle::state_at`] added into `x` (`n` entries, zero for the state itself).
    fn state_into(&self, tau: f64, x: &mut [f64]) {
        let (i, z) = self.mesh.locate(tau);
        self.interval_into(i, z, x);
    }

    /// The polynomial of interval `i` at local coordinate `z` in `[0, 1]`,
    /// added into `x` (`n` entries).
    fn interval_into(&self, i: usize, z: f64, x: &mut [f64]) {
        let m = self.mesh.degree;
        let mut stack = [0.0; 8];
        let mut heap = Vec::new();
        let basis = if m < stack.len() {
            &mut stack[..=m]
        } else {
            heap.resize(m + 1, 0.0);
            &mut heap[..]
        };
        lagrange_into(m, z, basis);
        self.add_combination(i, basis, x);
    }

    /// `sum_l basis[l] u_(i, l)` over the nodes of interval `i`, added into
    /// `x`: node `(i, l)` is `i m + l`, the last interval's end node 0
    /// (indexed directly, not through the `%` of [`Cycle::node`]).
    #[inline]
    fn add_combination(&self, i: usize, basis: &[f64], x: &mut [f64]) {
        let (m, n, last) = (self.mesh.degree, self.n, self.mesh.n_nodes());
        for (l, b) in basis.iter().enumerate() {
            let g = i * m + l;
            let g = if g == last { 0 } else { g };
            for (xj, uj) in x.iter_mut().zip(&self.u[g * n..(g + 1) * n]) {
                *xj += b * uj;
            }
        }
    }

    /// Samples `(tau, x)` at `per_interval` evenly spaced points of every
    /// interval (closing with `tau = 1`).
    pub fn samples(&self, per_interval: usize) -> Vec<(f64, Vec<f64>)> {
        let mut out = Vec::with_capacity(self.mesh.ntst() * per_interval + 1);
        self.each_sample(per_interval, |tau, x| out.push((tau, x.to_vec())));
        out
    }

    /// `visit(tau, x)` at the samples of [`Cycle::samples`], in their order,
    /// the state in one buffer (no allocation per sample).
    pub fn each_sample(&self, per_interval: usize, mut visit: impl FnMut(f64, &[f64])) {
        let mut x = vec![0.0; self.n];
        let t = &self.mesh.t;
        for i in 0..self.mesh.ntst() {
            for s in 0..per_interval {
                let tau = t[i] + (t[i + 1] - t[i]) * s as f64 / per_interval as f64;
                x.fill(0.0);
                // Interval `i` is where `Mesh::locate` finds `tau` (its
                // local coordinate computed as there) unless rounding put
                // `tau` on the next mesh point.
                if tau < t[i + 1] && tau < 1.0 {
                    self.interval_into(i, (tau - t[i]) / (t[i + 1] - t[i]), &mut x);
                } else {
                    self.state_into(tau, &mut x);
                }
                visit(tau, &x);
            }
        }
        // The closing sample at `tau = 1` is the state at 0.
        x.fill(0.0);
        self.state_into(0.0, &mut x);
        visit(1.0, &x);
    }

    /// Least and greatest value of component `j` over the orbit, to the
    /// accuracy of the mesh-point values: see [`Cycle::range_of`].
    pub fn range<S: VectorField>(&self, sys: &S, j: usize) -> (f64, f64) {
        self.range_of(sys, |x| x[j])
    }

    /// Least and greatest value of observable `k` of `sys`
    /// ([`VectorField::observable`]) over the orbit: see [`Cycle::range_of`].
    pub fn observable_range<S: VectorField>(&self, sys: &S, k: usize) -> (f64, f64) {
        self.range_of(sys, |x| sys.observable(k, x, &self.p))
    }

    /// Least and greatest value of the observable `g(x)` over the orbit of
    /// `sys`.
    ///
    /// Between mesh points the collocation polynomials are accurate to
    /// `O(h^(m+1))` only; at the mesh points the orbit is superconvergent
    /// (`O(h^(2m))` with Gauss points, `O(h^(2m-1))` with Radau points, like
    /// the period). An extreme is therefore not read off the polynomial: it
    /// is bracketed by the extreme of 8 samples per interval, and then
    /// maximised (Brent, started from the polynomial's extreme: `extreme_in`) over the value of [`Cycle::step_from_node`] — one
    /// collocation step of the same points from the mesh point before it, whose
    /// end value carries the mesh point's accuracy plus a local error
    /// `O(delta^(2m+1))` (Gauss) or `O(delta^(2m))` (Radau).
    pub fn range_of<S: VectorField>(&self, sys: &S, g: impl Fn(&[f64]) -> f64) -> (f64, f64) {
        let per = 8;
        let ntst = self.mesh.ntst();
        let m = self.mesh.degree;
        // The samples at the same local positions s / per of every interval.
        let basis: Vec<_> = (0..per)
            .map(|s| lagrange_values(m, s as f64 / per as f64))
            .collect();
        let mut x = vec![0.0; self.n];
        let mut values = Vec::with_capacity(ntst * per);
        for i in 0..ntst {
            for b in &basis {
                x.fill(0.0);
                self.add_combination(i, b, &mut x);
                values.push(g(&x));
            }
        }
        // Rounding in the values: the search stops where the value still to
        // gain is below it.
        let (lo_v, hi_v) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let floor = 4.0 * f64::EPSILON * (hi_v - lo_v + lo_v.abs().max(hi_v.abs()));
        let stepper = Stepper::new(sys, self);
        let pick = |sign: f64| {
            let best = (0..values.len())
                .max_by(|&a, &b| (sign * values[a]).total_cmp(&(sign * values[b])))
                .unwrap_or(0);
            let (i, s) = (best / per, best % per);
            let h = self.mesh.t[i + 1] - self.mesh.t[i];
            // The samples next to the best one bracket the extreme; at the
            // start of an interval the bracket reaches into the one before.
            let inside = self.extreme_in(
                &stepper,
                |x| sign * g(x),
                i,
                (
                    h * s.saturating_sub(1) as f64 / per as f64,
                    h * (s + 1) as f64 / per as f64,
                ),
                floor,
            );
            let value = if s == 0 {
                let before = (i + ntst - 1) % ntst;
                let hb = self.mesh.t[before + 1] - self.mesh.t[before];
                inside.max(self.extreme_in(
                    &stepper,
                    |x| sign * g(x),
                    before,
                    (hb * (per - 1) as f64 / per as f64, hb),
                    floor,
                ))
            } else {
                inside
            };
            sign * value
        };
        (pick(-1.0), pick(1.0))
    }

    /// Largest value of `f(x(t_i + delta))` for `delta` in `lo..=hi`, `x`
    /// the collocation step of `stepper` from mesh point `i`
    /// ([`Cycle::step_from_node`]), by Brent's method ([`brent_max`]) to
    /// `floor`.
    ///
    /// Each value costs a collocation step (a small Newton iteration), so
    /// the search starts where the interval's polynomial, the same curve
    /// to `O(h^(m+1))` at the cost of a basis evaluation, has its extreme
    /// (Brent's method on the polynomial): the steps are searched on
    /// [`NARROW`] of the bracket around it, and on the whole bracket only
    /// if the extreme found there lies on an inner edge of the narrowed one.
    /// Where the polynomial's extreme is an end of the bracket (within
    /// [`EDGE`] of it, a mesh point), which Brent's method approaches only
    /// by many short steps, that end's value is taken when the steps fall
    /// away from it over the narrowed bracket (at half and all of its
    /// width). The extremes equal those of the search over the whole
    /// bracket to the rounding of the values (jobs 3 and 4 of
    /// docs/performance.md: within 3e-14 relative; 8.5 collocation steps
    /// per extreme on job 4 instead of 15).
    fn extreme_in<S: VectorField>(
        &self,
        stepper: &Stepper<S>,
        f: impl Fn(&[f64]) -> f64,
        i: usize,
        (lo, hi): (f64, f64),
        floor: f64,
    ) -> f64 {
        let stepped = |delta: f64| f(&stepper.state(i, delta));
        let h = self.mesh.t[i + 1] - self.mesh.t[i];
        let mut x = vec![0.0; self.n];
        let polynomial = |delta: f64| {
            x.fill(0.0);
            self.interval_into(i, delta / h, &mut x);
            f(&x)
        };
        let (guess, _) = brent_max(polynomial, lo, hi, floor);
        let r = NARROW * (hi - lo);
        let near = EDGE * (hi - lo);
        if guess - lo <= near || hi - guess <= near {
            // The polynomial's extreme is the mesh point at the end of the
            // bracket: so is the steps', where they fall away from it.
            let (end, inward) = if guess - lo <= near {
                (lo, r)
            } else {
                (hi, -r)
            };
            let edge = stepped(end);
            let (half, full) = (stepped(end + 0.5 * inward), stepped(end + inward));
            if edge >= half && half >= full {
                return edge;
            }
        }
        let (a, b) = ((guess - r).max(lo), (guess + r).min(hi));
        let (at, value) = brent_max(&stepped, a, b, floor);
        // Twice Brent's tolerance in the abscissa: an extreme at the edge.
        let edge = 4e-10 * (b - a).max(at.abs());
        if (a > lo && at - a <= edge) || (b < hi && b - at <= edge) {
            brent_max(stepped, lo, hi, floor).1.max(value)
        } else {
            value
        }
    }

    /// The state at normalized time `t_i + delta` (`0 <= delta <= h_i`) by
    /// one collocation step from mesh point `i`: with the collocation points
    /// `c_k` of the mesh, the stages `X_k = u_i + delta T sum_l a_kl f(X_l)`,
    /// `a_kl = int_0^c_k L_l` (the Lagrange basis on the `c_k`), solved by
    /// Newton's method from the orbit's polynomial, and the end value
    /// `u_i + delta T sum_l b_l f(X_l)` (`b_l` the quadrature weights),
    /// evaluated as the value at 1 of the polynomial through `(0, u_i)` and
    /// the `(c_k, X_k)`, which it equals.
    /// Over the whole interval (`delta = h_i`) this is the orbit's own
    /// collocation step. Where Newton's method does not converge, the
    /// polynomial's value.
    pub fn step_from_node<S: VectorField>(&self, sys: &S, i: usize, delta: f64) -> Vec<f64> {
        Stepper::new(sys, self).state(i, delta)
    }

    /// Moves the orbit onto another mesh (same degree) by evaluating its polynomials.
    pub fn remesh(&self, mesh: Mesh) -> Cycle {
        let mut u = vec![0.0; mesh.n_nodes() * self.n];
        let mut nodes = u.chunks_exact_mut(self.n);
        for i in 0..mesh.ntst() {
            for (l, x) in (0..mesh.degree).zip(&mut nodes) {
                self.state_into(mesh.node_time(i, l), x);
            }
        }
        Cycle {
            mesh,
            u,
            period: self.period,
            p: self.p.clone(),
            n: self.n,
        }
    }
}

/// Unknowns `v` of a collocation system whose first part is node values on
/// `from` (`n` per node), moved onto `to`: the node values by evaluating
/// their polynomials ([`Cycle::remesh`]), the entries after them (period,
/// parameters) as they are. For vectors of the unknowns' shape that are not
/// orbits themselves: tangents, differences of orbits.
pub(crate) fn unknowns_on(v: &[f64], from: &Mesh, n: usize, to: &Mesh) -> Vec<f64> {
    let nn = from.n_nodes() * n;
    let mut moved = Cycle {
        mesh: from.clone(),
        u: v[..nn].to_vec(),
        period: 0.0,
        p: Vec::new(),
        n,
    }
    .remesh(to.clone())
    .u;
    moved.extend_from_slice(&v[nn..]);
    moved
}

/// One collocation step from a mesh point of an orbit ([`Cycle::step_from_node`]).
struct Stepper<'a, S: VectorField> {
    sys: &'a S,
    cycle: &'a Cycle,
    /// `a_kl = int_0^c_k L_l(s) ds`, row-major `m x m`.
    a: Vec<f64>,
    /// The Lagrange basis on the nodes `0, c_1, .., c_m`, at 1.
    end: Vec<f64>,
    /// The stage Jacobian last factored, with its interval and step: the
    /// searches for an extreme step from one mesh point by ever closer
    /// lengths, and a step within [`NEAR_STEP`] of that length starts its
    /// chord iterations from it.
    factored: RefCell<Option<(usize, f64, StageLu)>>,
}

/// The factored stage Jacobian of a [`Stepper`].
type StageLu = nalgebra::LU<f64, Dyn, Dyn>;

/// The share of its bracket around the polynomial's extreme that the search
/// for an extreme of the collocation steps starts on ([`Cycle::extreme_in`]).
const NARROW: f64 = 1.0 / 32.0;

/// A polynomial's extreme within this share of its bracket from an end is
/// taken to be at that end, a mesh point ([`Cycle::extreme_in`]).
const EDGE: f64 = 1e-9;

/// Steps within this fraction of the step of the last factored stage
/// Jacobian reuse it: the chord iterations then contract by about this
/// factor on the stiff components (where `delta T J` dominates).
const NEAR_STEP: f64 = 1e-2;

impl<'a, S: VectorField> Stepper<'a, S> {
    fn new(sys: &'a S, cycle: &'a Cycle) -> Self {
        let c = &cycle.mesh.nodes;
        let m = c.len();
        // sum_l a_kl c_l^q = c_k^(q+1) / (q+1), q = 0..m-1: the step integrates
        // polynomials of degree m-1 exactly from 0 to c_k.
        let vander = DMatrix::from_fn(m, m, |q, l| c[l].powi(q as i32));
        let lu = vander.lu();
        let mut a = vec![0.0; m * m];
        for k in 0..m {
            let rhs = DVector::from_fn(m, |q, _| c[k].powi(q as i32 + 1) / (q as f64 + 1.0));
            if let Some(row) = lu.solve(&rhs) {
                a[k * m..(k + 1) * m].copy_from_slice(row.as_slice());
            }
        }
        let nodes: Vec<f64> = std::iter::once(0.0).chain(c.iter().copied()).collect();
        let end = (0..=m)
            .map(|j| {
                (0..=m)
                    .filter(|&q| q != j)
                    .map(|q| (1.0 - nodes[q]) / (nodes[j] - nodes[q]))
                    .product()
            })
            .collect();
        Stepper {
            sys,
            cycle,
            a,
            end,
            factored: RefCell::new(None),
        }
    }

    /// The stages' Jacobian `I - delta T (a_kl J(X_l))` at the stages `stages`
    /// (`n` per stage), factored.
    fn stage_jacobian(&self, stages: &[f64], ht: f64) -> StageLu {
        let (n, m) = (self.cycle.n, self.cycle.mesh.degree);
        let mut jac = DMatrix::<f64>::identity(m * n, m * n);
        let mut jl = DMatrix::zeros(n, n);
        for l in 0..m {
            // Zeroed, as a new matrix would be: a hand-written Jacobian may
            // write its nonzero entries only.
            jl.fill(0.0);
            self.sys
                .jacobian(&stages[l * n..(l + 1) * n], &self.cycle.p, &mut jl);
            for k in 0..m {
                let w = ht * self.a[k * m + l];
                for r in 0..n {
                    for s in 0..n {
                        jac[(k * n + r, l * n + s)] -= w * jl[(r, s)];
                    }
                }
            }
        }
        jac.lu()
    }

    /// The stages `X_k` of the step of length `delta` from mesh point `i`
    /// (module documentation of [`Cycle::step_from_node`]), by chord
    /// iterations from the interval's polynomial: the Jacobian of the start
    /// (accurate to `O(h^(m+1))`) is kept while each correction at least
    /// halves, and renewed otherwise. `None` where they do not converge.
    fn stages(&self, i: usize, delta: f64, x0: &[f64]) -> Option<Vec<f64>> {
        let cyc = self.cycle;
        let (n, c) = (cyc.n, &cyc.mesh.nodes);
        let m = c.len();
        let h = cyc.mesh.t[i + 1] - cyc.mesh.t[i];
        let ht = delta * cyc.period;
        let mut stages = vec![0.0; m * n];
        for (k, ck) in c.iter().enumerate() {
            let basis = lagrange_values(m, ck * delta / h);
            for (l, bl) in basis.iter().enumerate() {
                for (x, u) in stages[k * n..(k + 1) * n]
                    .iter_mut()
                    .zip(cyc.node(cyc.mesh.node(i, l)))
                {
                    *x += bl * u;
                }
            }
        }
        let mut fs = vec![0.0; m * n];
        let mut residual = DVector::zeros(m * n);
        let kept = self.factored.borrow_mut().take();
        // `fresh`: the Jacobian was computed at the iterate the last
        // correction started from (full Newton there).
        let (mut lu_delta, mut lu, mut fresh) = match kept {
            Some((j, d, lu)) if j == i && (d - delta).abs() <= NEAR_STEP * delta.abs() => {
                (d, lu, false)
            }
            _ => (delta, self.stage_jacobian(&stages, ht), true),
        };
        let (mut converged, mut last) = (false, f64::INFINITY);
        for _ in 0..16 {
            for l in 0..m {
                let at = l * n..(l + 1) * n;
                self.sys.rhs(&stages[at.clone()], &cyc.p, &mut fs[at]);
            }
            for k in 0..m {
                for r in 0..n {
                    residual[k * n + r] = stages[k * n + r]
                        - x0[r]
                        - ht * (0..m)
                            .map(|l| self.a[k * m + l] * fs[l * n + r])
                            .sum::<f64>();
                }
            }
            // The correction, in place of the residual.
            if !lu.solve_mut(&mut residual) {
                return None;
            }
            let dx = &residual;
            // From the polynomial, rounding is reached in a few iterations.
            let size = stages
                .iter()
                .zip(dx.iter())
                .fold(0.0f64, |a, (x, d)| a.max(d.abs() / (1.0 + x.abs())));
            if !size.is_finite() {
                return None;
            }
            for (x, d) in stages.iter_mut().zip(dx.iter()) {
                *x -= d;
            }
            converged = size <= 1e-10;
            let stalled = size > 0.5 * last;
            // A Newton correction that no longer halves is rounding; a
            // chord correction that does not is a reason to renew.
            if size <= 4.0 * f64::EPSILON || (converged && stalled && fresh) {
                break;
            }
            fresh = stalled;
            if fresh {
                lu = self.stage_jacobian(&stages, ht);
                lu_delta = delta;
            }
            last = size;
        }
        *self.factored.borrow_mut() = Some((i, lu_delta, lu));
        converged.then_some(stages)
    }

    fn state(&self, i: usize, delta: f64) -> Vec<f64> {
        let cyc = self.cycle;
        let n = cyc.n;
        let m = cyc.mesh.degree;
        let x0 = cyc.node(cyc.mesh.node(i, 0)).to_vec();
        if delta == 0.0 {
            return x0;
        }
        let Some(stages) = self.stages(i, delta, &x0) else {
            return cyc.state_at(cyc.mesh.t[i] + delta);
        };
        // The step's polynomial through (0, u_i) and the stages (c_k, X_k),
        // at 1: equal in exact arithmetic to the quadrature
        // u_i + delta T sum_l b_l f(X_l), but without multiplying the stages'
        // rounding by the stiffness (rates of 1e12 while the block sticks;
        // with Radau points, c_m = 1, it is the last stage).
        (0..n)
            .map(|r| {
                self.end[0] * x0[r]
                    + (0..m)
                        .map(|k| self.end[k + 1] * stages[k * n + r])
                        .sum::<f64>()
            })
            .collect()
    }
}

/// Largest value of `f` on `[a, b]` by Brent's method (golden section with
/// parabolic interpolation; Brent 1973, ch. 5), to a relative tolerance of
/// `1e-10` in the abscissa, or until the parabolas through the last three
/// points promise less than `floor` more twice in a row (a vertex `d` from
/// the best point, curvature `c`: a gain of `c d^2`): near a maximum `f` is
/// flat, so the value is then exact to rounding. (Not `sqrt(eps)`: the slip
/// of a stiff orbit can be as narrow as 1e-8 of its mesh interval, and its
/// peak velocity was then off by 1e-7.)
fn brent_max(mut f: impl FnMut(f64) -> f64, mut a: f64, mut b: f64, floor: f64) -> (f64, f64) {
    let g = 0.5 * (3.0 - 5f64.sqrt());
    let mut neg = |x: f64| -f(x);
    let (mut x, mut w, mut v) = (a + g * (b - a), a + g * (b - a), a + g * (b - a));
    let mut fx = neg(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    // The last parabolic step promised less than `floor`.
    let mut settled = false;
    // Also the ends: the extreme may sit on the bracket's edge (a mesh point).
    let (fa, fb) = (neg(a), neg(b));
    let (a_start, b_start) = (a, b);
    for _ in 0..100 {
        let xm = 0.5 * (a + b);
        let tol1 = 1e-10 * x.abs().max((b - a).abs()).max(f64::MIN_POSITIVE);
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let c = ((fw - fx) / (w - x) - (fv - fx) / (v - x)) / (w - v);
                let small = c > 0.0 && c * d * d <= floor;
                if small && settled {
                    break;
                }
                settled = small;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol1.copysign(xm - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = g * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = neg(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    // The best of the ends and the search (as `f64::min`, NaN only if all are).
    let best = fx.min(fa).min(fb);
    let at = if best == fx {
        x
    } else if best == fa {
        a_start
    } else {
        b_start
    };
    (at, -best)
}
