//! Newton's method on the collocation system allocates nothing per
//! iteration once its storage is warm: a counting global allocator (this
//! test thread's allocations only) compares a run of 2 iterations with one
//! of 6 from the same start.

use continuation::error::NewtonFailure;
use continuation::newton::NewtonSettings;
use continuation::periodic::collocation::Collocation;
use continuation::periodic::cycle::Cycle;
use continuation::periodic::mesh::Mesh;
use continuation::periodic::newton::{newton_bordered, unit_row};
use continuation::{ContinuationError, Scalar, VectorField};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

fn count() {
    // `try_with`: nothing to count while the thread is being torn down.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

/// Stuart–Landau, `Z' = (beta + i w) Z - Z |Z|^2 + i g Z |Z|^2`, `beta = p`:
/// the cycle `|Z|^2 = beta` with angular frequency `w + g beta`.
struct StuartLandau;

impl VectorField for StuartLandau {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let rot = r2 * 0.5 + 2.0;
        out[0] = (p[0] - r2) * x[0] - rot * x[1];
        out[1] = rot * x[0] + (p[0] - r2) * x[1];
    }
}

#[test]
fn a_newton_iteration_on_the_collocation_system_allocates_nothing() {
    let sys = StuartLandau;
    // Off the cycle at beta = 1 (radius 1.05, period 2 % long), so that
    // every iteration takes a step; 20 intervals: the intervals run in turn.
    let mesh = Mesh::uniform(20, 4, Default::default());
    let mut u = Vec::new();
    for i in 0..mesh.ntst() {
        for l in 0..mesh.degree {
            let t = 2.0 * std::f64::consts::PI * mesh.node_time(i, l);
            u.extend([1.05 * t.cos(), 1.05 * t.sin()]);
        }
    }
    let cycle = Cycle {
        mesh,
        u,
        period: 1.02 * 2.0 * std::f64::consts::PI / 2.5,
        p: vec![1.0],
        n: 2,
    };
    let coll = Collocation::new(&sys, &cycle, 0);
    let z0 = coll.unknowns(&cycle);
    let row = unit_row(z0.len(), z0.len() - 1);
    // Tolerances nobody meets: the runs end at the iteration limit.
    let run = |max_iter: usize| {
        let settings = NewtonSettings {
            step_tol: 0.0,
            residual_tol: 0.0,
            max_iter,
        };
        let mut z = z0.clone();
        let before = allocations();
        let result = newton_bordered(&coll, &mut z, &settings, &row, &z0);
        let used = allocations() - before;
        match result {
            Err(ContinuationError::Newton {
                iterations, reason, ..
            }) => {
                assert_eq!(reason, NewtonFailure::MaxIterations);
                assert_eq!(iterations, max_iter);
            }
            other => panic!("expected the iteration limit, got {other:?}"),
        }
        used
    };
    let (short, long) = (run(2), run(6));
    assert!(short > 0, "the first iterations allocate the storage");
    assert_eq!(
        long,
        short,
        "iterations 3 to 6 allocated {} times",
        long as isize - short as isize
    );
}
