//! Cost of the solver's building blocks on the reference chain of N rods
//! (each with a slider: 2N bodies, 6N coordinates) for N = 10, 100, 1000:
//! one residual, one analytic Jacobian, one real and one complex numeric
//! factorisation (and the real one with faer's COLAMD sparse LU for
//! comparison), one real and one complex solve, and ten integrator steps.
//! Each should grow about linearly with N. Results: docs/performance.md.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use quakejoint_solver::integrator::radau5::{form_complex, form_real};
use quakejoint_solver::linalg::scalar::Complex64;
use quakejoint_solver::linalg::{FaerCache, KktSolver, LinearSolver};
use quakejoint_solver::reference::chain;
use quakejoint_solver::*;

const SIZES: [usize; 3] = [10, 100, 1000];

struct Setup {
    asm: Arc<Assembly>,
    q: Vec<f64>,
    v: Vec<f64>,
    lam: Vec<f64>,
}

fn setup(n: usize) -> Setup {
    let asm = Arc::new(Assembly::new(&chain(n, 2.0e4), &AssemblyOptions::default()).unwrap());
    // a moving state: a few steps into the fall
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default()).unwrap();
    sim.run(0.05, &mut NoObserver).unwrap();
    Setup { q: sim.positions().to_vec(), v: sim.velocities().to_vec(), lam: sim.multipliers().to_vec(), asm }
}

struct StopAfter(u32);

impl Observer for StopAfter {
    fn step(&mut self, _: &mut StepView<'_>) -> bool {
        self.0 -= 1;
        self.0 > 0
    }
}

fn kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("chain");
    group.sample_size(20);
    for n in SIZES {
        let s = setup(n);
        let asm = &s.asm;
        let mut ws = asm.workspace();
        group.bench_with_input(BenchmarkId::new("residual", n), &n, |b, _| {
            b.iter(|| asm.residual(&mut ws, 0.05, black_box(&s.q), &s.v, &s.lam))
        });
        let mut jac = asm.jacobian_values();
        group.bench_with_input(BenchmarkId::new("jacobian", n), &n, |b, _| {
            b.iter(|| asm.jacobian(&mut ws, 0.05, black_box(&s.q), &s.v, &s.lam, &mut jac))
        });
        let sym = asm.block_structure();
        let mut cache = FaerCache::default();
        let desc = |p: usize| format!("{p}");
        let h = 1e-3;
        let mut real = KktSolver::<f64>::new(sym, LinearSolver::Block);
        group.bench_with_input(BenchmarkId::new("factor_real", n), &n, |b, _| {
            b.iter(|| {
                real.factor(sym, &mut cache, &|out: &mut [f64]| form_real(asm, 3.64 / h, &jac, out), &desc).unwrap()
            })
        });
        let mut faer = KktSolver::<f64>::new(sym, LinearSolver::Faer);
        group.bench_with_input(BenchmarkId::new("factor_real_faer_colamd", n), &n, |b, _| {
            b.iter(|| {
                faer.factor(sym, &mut cache, &|out: &mut [f64]| form_real(asm, 3.64 / h, &jac, out), &desc).unwrap()
            })
        });
        let cz = Complex64::new(2.68 / h, 3.05 / h);
        let mut cplx = KktSolver::<Complex64>::new(sym, LinearSolver::Block);
        group.bench_with_input(BenchmarkId::new("factor_complex", n), &n, |b, _| {
            b.iter(|| {
                cplx.factor(sym, &mut cache, &|out: &mut [Complex64]| form_complex(asm, cz, &jac, out), &desc).unwrap()
            })
        });
        // the right-hand side is restored before every solve (solving in
        // place repeatedly would shrink it into subnormal numbers)
        let (rhs0, mut rhs) = (vec![1.0; sym.dim()], vec![0.0; sym.dim()]);
        group.bench_with_input(BenchmarkId::new("solve_real", n), &n, |b, _| {
            b.iter(|| {
                rhs.copy_from_slice(&rhs0);
                real.solve(sym, &mut cache, black_box(&mut rhs)).unwrap()
            })
        });
        let (rhs0_c, mut rhs_c) = (vec![Complex64::new(1.0, 0.5); sym.dim()], vec![Complex64::default(); sym.dim()]);
        group.bench_with_input(BenchmarkId::new("solve_complex", n), &n, |b, _| {
            b.iter(|| {
                rhs_c.copy_from_slice(&rhs0_c);
                cplx.solve(sym, &mut cache, black_box(&mut rhs_c)).unwrap()
            })
        });
        group.bench_with_input(BenchmarkId::new("ten_steps", n), &n, |b, _| {
            b.iter_batched(
                || Radau5::new(asm.clone(), IntegratorOptions::default()).unwrap(),
                |mut sim| {
                    sim.run(10.0, &mut StopAfter(10)).unwrap();
                    sim
                },
                criterion::BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
