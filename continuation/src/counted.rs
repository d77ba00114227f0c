//! Counting the evaluations of a vector field.
//!
//! [`Counted`] wraps a [`VectorField`], delegates every method to it and
//! counts the calls of [`rhs`](VectorField::rhs) by the derivative order of
//! the scalar type: plain `f64` values, dual numbers (Jacobians, parameter
//! derivatives), hyper-dual numbers (second derivatives) and the nested duals
//! of the higher normal-form coefficients. The field itself carries no
//! counter: an analysis that is not measured pays nothing.
//!
//! An analysis builds its fields through a [`Wrap`]: [`AsIs`] leaves them
//! as they are, [`Counting`] wraps every field in a [`Counted`] that adds to
//! one shared tally, so that the evaluations of all the fields an analysis
//! builds (an equilibrium model, the same model in other variables for its
//! cycles) add up.

use crate::system::{JointDirection, VectorField};
use crate::Scalar;
use nalgebra::DMatrix;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Number of evaluation kinds of [`EvalCounts`].
pub const N_EVAL_KINDS: usize = 6;

/// Names of the evaluation kinds of [`EvalCounts`], in order: plain `f64`,
/// then scalar types carrying derivatives up to order 1 (`Dual64`), 2
/// (`HyperDual64`, `Dual<Dual64>`), 3 (`HyperHyperDual64`, three nested
/// duals), 4 and 5 (nested duals of `hopf_series`).
pub const EVAL_KINDS: [&str; N_EVAL_KINDS] =
    ["f64", "order1", "order2", "order3", "order4", "order5"];

/// The index into [`EVAL_KINDS`] of an evaluation with scalar type `D`. The
/// kind is read from the size of `D` in `f64` components,
/// `c = size_of::<D>() / 8`, as `ceil(log2 c)`: 1 component is a plain
/// value, 2 a first-order dual, 4 a hyper-dual or twice-nested dual (order
/// 2), 8 order 3, 16 order 4, 32 (and more) order 5. This is the derivative
/// order for the hyper-dual and nested dual types the engine uses; a type of
/// another layout is filed by its size (a multi-direction first-order
/// `DualVec` by its number of components, a double-double value, two `f64`,
/// as order 1). The index is a compile-time constant of each instantiation.
#[inline(always)]
pub fn eval_kind<D>() -> usize {
    let components = (std::mem::size_of::<D>() / 8).max(1);
    (components.next_power_of_two().trailing_zeros() as usize).min(N_EVAL_KINDS - 1)
}

/// Evaluation counters by kind ([`EVAL_KINDS`]), shared by all threads
/// (relaxed atomics).
#[derive(Debug, Default)]
pub struct EvalCounts([AtomicU64; N_EVAL_KINDS]);

impl EvalCounts {
    /// Counters at zero.
    pub fn new() -> EvalCounts {
        EvalCounts::default()
    }

    /// The counts, indexed like [`EVAL_KINDS`].
    pub fn get(&self) -> [u64; N_EVAL_KINDS] {
        std::array::from_fn(|k| self.0[k].load(Ordering::Relaxed))
    }

    /// Sets every counter to zero.
    pub fn reset(&self) {
        for c in &self.0 {
            c.store(0, Ordering::Relaxed);
        }
    }

    /// Adds `n` evaluations of kind `kind`.
    fn add(&self, kind: usize, n: u64) {
        self.0[kind].fetch_add(n, Ordering::Relaxed);
    }
}

/// A vector field that counts its evaluations ([`EvalCounts`]) and is
/// otherwise the field it wraps: every method of [`VectorField`] is
/// delegated.
///
/// A Jacobian ([`VectorField::jacobian`]) is delegated too (a hand-written
/// one stays in use) and counted as `n` order-1 evaluations, the `n` dual
/// columns the default Jacobian evaluates; a Jacobian by dual numbers
/// through [`crate::system::jacobian`] thus costs what it did before
/// wrapping, and a hand-written one is counted at that nominal cost.
#[derive(Debug)]
pub struct Counted<S> {
    inner: S,
    counts: Arc<EvalCounts>,
}

impl<S> Counted<S> {
    /// `inner` with counters of its own, at zero.
    pub fn new(inner: S) -> Counted<S> {
        Counted::sharing(inner, Arc::new(EvalCounts::new()))
    }

    /// `inner` counted into `counts`, which other fields may share.
    pub fn sharing(inner: S, counts: Arc<EvalCounts>) -> Counted<S> {
        Counted { inner, counts }
    }

    /// The evaluations so far, indexed like [`EVAL_KINDS`].
    pub fn counts(&self) -> [u64; N_EVAL_KINDS] {
        self.counts.get()
    }

    /// The field wrapped.
    pub fn inner(&self) -> &S {
        &self.inner
    }
}

impl<S: VectorField> VectorField for Counted<S> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn n_params(&self) -> usize {
        self.inner.n_params()
    }
    fn param_name(&self, k: usize) -> String {
        self.inner.param_name(k)
    }
    #[inline]
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        self.counts.add(eval_kind::<D>(), 1);
        self.inner.rhs(x, p, out);
    }
    fn newton_update(&self, x: &mut [f64], dx: &[f64]) {
        self.inner.newton_update(x, dx);
    }
    fn has_implicit_form(&self) -> bool {
        self.inner.has_implicit_form()
    }
    #[inline]
    fn implicit_rhs<D: Scalar>(&self, x: &[D], p: &[D], rho: &mut [D], g: &mut [D]) {
        self.counts.add(eval_kind::<D>(), 1);
        self.inner.implicit_rhs(x, p, rho, g);
    }
    fn n_observables(&self) -> usize {
        self.inner.n_observables()
    }
    fn observable(&self, k: usize, x: &[f64], p: &[f64]) -> f64 {
        self.inner.observable(k, x, p)
    }
    /// Counted at its nominal cost, as before it was one evaluation: a
    /// value and `n + 1` dual columns.
    fn first_order(
        &self,
        x: &[f64],
        p: &[f64],
        k: usize,
        out: (&mut [f64], &mut DMatrix<f64>, &mut [f64]),
    ) {
        self.counts.add(eval_kind::<f64>(), 1);
        self.counts
            .add(eval_kind::<num_dual::Dual64>(), self.dim() as u64 + 1);
        self.inner.first_order(x, p, k, out);
    }
    /// Counted at its nominal cost, as before it was one evaluation: one
    /// hyper-dual evaluation per direction `w_j`.
    fn derivatives_along(
        &self,
        x: &[f64],
        p: &[f64],
        u: JointDirection,
        ws: &[JointDirection],
        out: (&mut [f64], &mut [f64], &mut [f64]),
    ) {
        self.counts
            .add(eval_kind::<num_dual::HyperDual64>(), ws.len() as u64);
        self.inner.derivatives_along(x, p, u, ws, out);
    }
    fn jacobian(&self, x: &[f64], p: &[f64], jac: &mut DMatrix<f64>) {
        self.counts
            .add(eval_kind::<num_dual::Dual64>(), self.dim() as u64);
        self.inner.jacobian(x, p, jac);
    }
}

/// How an analysis builds the vector fields it evaluates: as they are
/// ([`AsIs`]) or wrapped ([`Counting`]). An analysis generic over `Wrap`
/// evaluates only fields it has passed through [`field`](Wrap::field).
pub trait Wrap: Sync {
    /// The field `S` as the analysis evaluates it.
    type Field<S: VectorField>: VectorField;

    /// Wraps `field`.
    fn field<S: VectorField>(&self, field: S) -> Self::Field<S>;
}

/// The fields as they are: no wrapper, no cost.
#[derive(Clone, Copy, Debug, Default)]
pub struct AsIs;

impl Wrap for AsIs {
    type Field<S: VectorField> = S;

    fn field<S: VectorField>(&self, field: S) -> S {
        field
    }
}

/// Every field [`Counted`] into one shared tally.
#[derive(Clone, Debug, Default)]
pub struct Counting {
    counts: Arc<EvalCounts>,
}

impl Counting {
    /// A tally at zero.
    pub fn new() -> Counting {
        Counting::default()
    }

    /// The evaluations of all fields built so far, indexed like [`EVAL_KINDS`].
    pub fn counts(&self) -> [u64; N_EVAL_KINDS] {
        self.counts.get()
    }

    /// Sets the tally to zero.
    pub fn reset(&self) {
        self.counts.reset();
    }
}

impl Wrap for Counting {
    type Field<S: VectorField> = Counted<S>;

    fn field<S: VectorField>(&self, field: S) -> Counted<S> {
        Counted::sharing(field, Arc::clone(&self.counts))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{eval, jacobian, param_derivative, second_derivative, JointDirection};
    use num_dual::{Dual, Dual64, HyperDual64, HyperHyperDual64};

    /// `f = (x0 x1 + p0, sin x0)`, with a named parameter and one observable.
    struct Toy;
    impl VectorField for Toy {
        fn dim(&self) -> usize {
            2
        }
        fn n_params(&self) -> usize {
            1
        }
        fn param_name(&self, _: usize) -> String {
            "a".into()
        }
        fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
            out[0] = x[0] * x[1] + p[0];
            out[1] = x[0].sin();
        }
        fn n_observables(&self) -> usize {
            1
        }
        fn observable(&self, _: usize, x: &[f64], _: &[f64]) -> f64 {
            x[0] + x[1]
        }
    }

    /// [`Toy`] with a hand-written Jacobian, off by one in a corner so that
    /// its use shows.
    struct OwnJacobian;
    impl VectorField for OwnJacobian {
        fn dim(&self) -> usize {
            2
        }
        fn n_params(&self) -> usize {
            1
        }
        fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
            Toy.rhs(x, p, out)
        }
        fn jacobian(&self, x: &[f64], _: &[f64], jac: &mut DMatrix<f64>) {
            *jac = DMatrix::from_row_slice(2, 2, &[x[1], x[0], x[0].cos(), 1.0]);
        }
    }

    #[test]
    fn kinds_follow_the_derivative_order() {
        type N5 = Dual<Dual<Dual<Dual<Dual64>>>>;
        let kinds = [
            eval_kind::<f64>(),
            eval_kind::<Dual64>(),
            eval_kind::<HyperDual64>(),
            eval_kind::<Dual<Dual64>>(),
            eval_kind::<HyperHyperDual64>(),
            eval_kind::<Dual<Dual<Dual64>>>(),
            eval_kind::<Dual<Dual<Dual<Dual64>>>>(),
            eval_kind::<N5>(),
        ];
        assert_eq!(kinds, [0, 1, 2, 2, 3, 3, 4, 5]);
    }

    #[test]
    fn counts_match_the_calls_made_and_values_are_the_fields() {
        let c = Counted::new(Toy);
        let (x, p) = ([0.3, -1.2], [0.7]);
        for _ in 0..5 {
            assert_eq!(eval(&c, &x, &p), eval(&Toy, &x, &p));
        }
        // 2 dual columns per Jacobian, 3 Jacobians.
        for _ in 0..3 {
            assert_eq!(jacobian(&c, &x, &p), jacobian(&Toy, &x, &p));
        }
        assert_eq!(
            param_derivative(&c, &x, &p, 0),
            param_derivative(&Toy, &x, &p, 0)
        );
        let u = JointDirection::state(&[1.0, 0.5]);
        for _ in 0..2 {
            assert_eq!(
                second_derivative(&c, &x, &p, u, u),
                second_derivative(&Toy, &x, &p, u, u)
            );
        }
        let mut out = [HyperHyperDual64::from(0.0); 2];
        let xh = x.map(HyperHyperDual64::from);
        c.rhs(&xh, &[HyperHyperDual64::from(p[0])], &mut out);
        assert_eq!(c.counts(), [5, 3 * 2 + 1, 2, 1, 0, 0]);
        // Everything else is the wrapped field's.
        assert_eq!((c.dim(), c.n_params(), c.param_name(0)), (2, 1, "a".into()));
        assert_eq!(
            (c.n_observables(), c.observable(0, &x, &p)),
            (1, x[0] + x[1])
        );
    }

    /// The one-pass derivatives are delegated and counted at the cost of
    /// the evaluations they replace: a value and `n + 1` dual columns, one
    /// hyper-dual evaluation per direction.
    #[test]
    fn one_pass_derivatives_are_counted_at_their_nominal_cost() {
        let c = Counted::new(Toy);
        let (x, p) = ([0.3, -1.2], [0.7]);
        let (mut f, mut fp, mut jac) = ([0.0; 2], [0.0; 2], DMatrix::zeros(2, 2));
        c.first_order(&x, &p, 0, (&mut f, &mut jac, &mut fp));
        assert_eq!(jac, jacobian(&Toy, &x, &p));
        let (u, e0, e1) = ([1.0, 0.5], [1.0, 0.0], [0.0, 1.0]);
        let ws = [
            JointDirection::state(&e0),
            JointDirection::state(&e1),
            JointDirection { x: &[], p: &[1.0] },
        ];
        let (mut du, mut dw, mut duw) = ([0.0; 2], [0.0; 6], [0.0; 6]);
        c.derivatives_along(
            &x,
            &p,
            JointDirection::state(&u),
            &ws,
            (&mut du, &mut dw, &mut duw),
        );
        assert_eq!(c.counts(), [1, 2 + 1, 3, 0, 0, 0]);
    }

    #[test]
    fn a_hand_written_jacobian_is_kept_and_counted_by_its_columns() {
        let c = Counted::new(OwnJacobian);
        let (x, p) = ([0.3, -1.2], [0.7]);
        assert_eq!(jacobian(&c, &x, &p)[(1, 1)], 1.0);
        assert_eq!(c.counts(), [0, 2, 0, 0, 0, 0]);
    }

    #[test]
    fn fields_of_one_tally_add_up_across_threads() {
        let tally = Counting::new();
        let (a, b) = (tally.field(Toy), tally.field(Toy));
        let (x, p) = ([0.3, -1.2], [0.7]);
        std::thread::scope(|s| {
            for field in [&a, &b] {
                s.spawn(move || {
                    for _ in 0..1000 {
                        eval(field, &x, &p);
                    }
                });
            }
        });
        assert_eq!(tally.counts(), [2000, 0, 0, 0, 0, 0]);
        assert_eq!(a.counts(), tally.counts());
        tally.reset();
        assert_eq!(tally.counts(), [0; N_EVAL_KINDS]);
        // AsIs leaves the field alone.
        assert_eq!(eval(&AsIs.field(Toy), &x, &p), eval(&Toy, &x, &p));
    }
}
