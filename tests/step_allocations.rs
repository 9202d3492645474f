//! The time-step loop allocates nothing: a counting global allocator around Newmark steps of the
//! full drillstring system (wall contact and bit engaged, strain tangent refreshed) and the
//! stress envelope's recording (fatigue rainflow counters included). This file
//! holds a single test so that no other test allocates concurrently.

use drillopt::fem::SectionStress;
use drillopt::integrate::{Newmark, NewmarkSettings, StepOutcome};
use drillopt::model::{BasisSpec, FamilySize};
use drillopt::problem::Problem;
use drillopt::sim::{Dynamics, Effects, StressEnvelope, preloaded_equilibrium};
use nalgebra::DVector;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn newmark_steps_of_the_drillstring_allocate_nothing() {
    let p = Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_mc2014.toml"
    ))
    .unwrap();
    // Every kind of basis vector: modes of each family and the bit's static corrections.
    let basis = BasisSpec::PerFamily {
        bending: FamilySize::Count(10),
        torsional: FamilySize::Count(2),
        axial: FamilySize::Count(2),
        static_corrections: true,
        steady_shapes: true,
    };
    // With the steady drilling state's shapes (the default basis's last kind of vector).
    let mesh = drillopt::model::Mesh {
        elements: 30,
        basis,
    };
    let model = drillopt::sim::reduced_model(&p.model, &mesh, p.operating_point).unwrap();
    assert!(model.basis.counts().steady_shapes > 0, "{:?}", model.steady);
    let (q, _) = preloaded_equilibrium(&model, p.operating_point, Effects::ALL).unwrap();
    let n = model.size();
    let mut sys = Dynamics::new(&model, p.operating_point, Effects::ALL);
    // refresh_after = 0 forces the strain-tangent refresh at every iteration, so that path is
    // exercised too.
    let settings = NewmarkSettings {
        refresh_after: 0,
        early_reject: f64::INFINITY,
        ..Default::default()
    };
    let mut nm = Newmark::new(settings, 0.0, q, DVector::zeros(n), DVector::zeros(n));
    assert!(nm.consistent_acceleration(&mut sys));
    let h = 1e-4;
    // The stress envelope recorded at every accepted step: section loads, fibre stresses of the
    // spinning sections and their rainflow counters (buffers allocated here, once).
    let stress = [SectionStress::new(
        &model.string,
        model.global.layout.element(0).length,
    )];
    let mut envelope = StressEnvelope::for_string(&model.string, &model.global.layout, 0.0);
    let mut defects = vec![[0.0; 2]; model.elements()];
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for _ in 0..20 {
        let outcome = nm.attempt(&mut sys, h);
        assert!(
            matches!(outcome, StepOutcome::Converged { .. }),
            "{outcome:?}"
        );
        nm.accept(h);
        // The observation recorded after each accepted step.
        std::hint::black_box(sys.observe_step(&nm.q, &nm.v, &nm.a));
        let spin = p.operating_point.omega * nm.t;
        // With the reduced model's force-summation recovery of the axial force and torque.
        assert!(sys.force_summation_defects(&mut defects));
        envelope.record(nm.t, sys.displacement_full(), spin, &stress, &defects);
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert!(
        sys.contacts.iter().any(|c| c.active),
        "the steps must involve wall contact"
    );
    assert!(sys.bit.force < 0.0, "and the bit");
    assert_eq!(after - before, 0, "allocations during 20 time steps");
}
