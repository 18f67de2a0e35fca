//! The hot functions of `motion` allocate nothing once their buffers exist: smoothing (after
//! the first call on the longest trajectory), differentiation, unwrapping. Allocations are
//! counted per thread by a wrapping global allocator, so parallel tests do not interfere.

use articula::motion::derive::{differentiate, differentiate_quaternions, second_derivative};
use articula::motion::smooth::{SmoothSpec, Smoother};
use articula::motion::unwrap::{AngleUnit, unwrap_angles};
use nalgebra::{UnitQuaternion, Vector3};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCS.with(|c| c.get());
    f();
    ALLOCS.with(|c| c.get()) - before
}

#[test]
fn smoothing_allocates_nothing_after_setup() {
    let dt = 1.0 / 120.0;
    let x: Vec<f64> = (0..500).map(|k| (k as f64 * 0.05).sin()).collect();
    let q: Vec<UnitQuaternion<f64>> = (0..500)
        .map(|k| UnitQuaternion::from_scaled_axis(Vector3::new(0.01 * k as f64, 0.3, 0.0)))
        .collect();
    for spec in [
        SmoothSpec::Gaussian { sigma_s: 0.02 },
        SmoothSpec::Butterworth {
            cutoff_hz: 6.0,
            order: 3,
        },
    ] {
        let mut s = Smoother::new(spec, dt).unwrap();
        s.reserve(500);
        let (mut a, mut b) = (x.clone(), q.clone());
        let n = allocations(|| {
            s.smooth(&mut a);
            s.smooth(&mut a[..300]);
            s.smooth_quaternions(&mut b);
        });
        assert_eq!(n, 0, "{spec}: {n} allocations");
    }
    // without reserve, the first call sizes the buffers and later ones reuse them
    let mut s = Smoother::new(SmoothSpec::Gaussian { sigma_s: 0.01 }, dt).unwrap();
    let mut a = x.clone();
    s.smooth(&mut a);
    assert_eq!(allocations(|| s.smooth(&mut a)), 0);
}

#[test]
fn derivatives_and_unwrap_allocate_nothing() {
    // the counter sees allocations at all
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 10]))) > 0);
    let dt = 0.01;
    let x: Vec<f64> = (0..200).map(|k| (k as f64 * 0.1).sin() * 200.0).collect();
    let q: Vec<UnitQuaternion<f64>> = (0..200)
        .map(|k| UnitQuaternion::from_scaled_axis(Vector3::new(0.02 * k as f64, 0.1, 0.0)))
        .collect();
    let (mut d, mut dd) = (vec![0.0; 200], vec![0.0; 200]);
    let mut w = vec![Vector3::zeros(); 200];
    let mut y = x.clone();
    let n = allocations(|| {
        differentiate(&x, dt, &mut d);
        second_derivative(&x, dt, &mut dd);
        differentiate_quaternions(&q, dt, &mut w);
        unwrap_angles(AngleUnit::Degrees, &mut y);
    });
    assert_eq!(n, 0);
}
