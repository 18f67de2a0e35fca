//! Hot loops allocate nothing: once a `Workspace`, a `Stepper` and a `ComputedTorque` exist,
//! `rnea`, `crba`, the bias terms, `aba`, `forward_dynamics_cholesky`, the energy functions,
//! a controller evaluation and a step of every integrator make no heap allocation. A counting
//! global allocator (per thread, so the test harness's own threads do not count) proves it.

use articula::dynamics::samples::{SplitMix64, euler_avatar, random_configuration, random_tree};
use articula::dynamics::{
    ComputedTorque, Gains, Integrator, Reference, Stepper, Workspace, aba, coriolis_terms, crba,
    forward_dynamics_cholesky, gravity_terms, kinetic_energy, nonlinear_effects, potential_energy,
    rnea, spatial_momentum,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f`.
fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn dynamics_calls_allocate_nothing() {
    for model in [random_tree(15, 7, true), euler_avatar()] {
        let mut rng = SplitMix64(9);
        let mut q = vec![0.0; model.nq];
        random_configuration(&model, &mut rng, &mut q);
        if model.name == "euler_avatar" {
            q.iter_mut().for_each(|x| *x *= 0.3);
        }
        let v = vec![0.4; model.nv];
        let a = vec![-0.3; model.nv];
        let tau = vec![1.0; model.nv];
        let mut ws = Workspace::new(&model);
        let name = model.name.clone();
        let check = |what: &str, n: usize| assert_eq!(n, 0, "{name}: {what} allocated {n} times");

        check(
            "rnea",
            allocations(|| _ = rnea(&model, &mut ws, &q, &v, &a, None)),
        );
        check("crba", allocations(|| _ = crba(&model, &mut ws, &q)));
        check(
            "gravity_terms",
            allocations(|| _ = gravity_terms(&model, &mut ws, &q)),
        );
        check(
            "coriolis_terms",
            allocations(|| _ = coriolis_terms(&model, &mut ws, &q, &v)),
        );
        check(
            "nonlinear_effects",
            allocations(|| _ = nonlinear_effects(&model, &mut ws, &q, &v)),
        );
        check(
            "aba",
            allocations(|| _ = aba(&model, &mut ws, &q, &v, &tau, None).unwrap()),
        );
        check(
            "forward_dynamics_cholesky",
            allocations(|| {
                _ = forward_dynamics_cholesky(&model, &mut ws, &q, &v, &tau, None).unwrap()
            }),
        );
        check(
            "energy",
            allocations(|| {
                kinetic_energy(&model, &mut ws, &q, &v);
                potential_energy(&model, &mut ws, &q);
                spatial_momentum(&model, &mut ws, &q, &v);
            }),
        );

        // a controller evaluation against a two-sample reference
        let reference = Reference {
            time: vec![0.0, 1.0],
            q: vec![q.clone(), q.clone()],
            v: vec![v.clone(), v.clone()],
            a: vec![a.clone(), a.clone()],
        };
        let mut ctrl = ComputedTorque::new(&model, Gains::scalar(100.0, 20.0), 0.1).unwrap();
        check(
            "controller",
            allocations(|| _ = ctrl.torque(&reference, 0.3, &q, &v)),
        );

        // one step of every integrator (the first adaptive step included)
        for integrator in [
            Integrator::Euler,
            Integrator::SemiImplicitEuler,
            Integrator::Rk4,
            "dopri5:1e-6".parse().unwrap(),
        ] {
            let mut stepper = Stepper::new(&model, integrator);
            let (mut qs, mut vs) = (q.clone(), v.clone());
            let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
                acc.copy_from_slice(aba(&model, &mut ws, q, v, &tau, None)?.as_slice());
                Ok(())
            };
            let n = allocations(|| {
                stepper
                    .step(&model, 0.0, 1e-3, &mut qs, &mut vs, &mut f)
                    .unwrap();
            });
            check(&format!("a {integrator} step"), n);
        }
    }
    // the counter works: a Vec allocates
    assert_eq!(allocations(|| drop(std::hint::black_box(vec![1u8; 10]))), 1);
}
