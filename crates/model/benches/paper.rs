//! Building blocks of the solver on the reference (paper) model, single
//! thread unless stated: one residual (the paper's f(t, q)), the Jacobian by
//! dense finite differences, by coloured finite differences (serial and on
//! 1 and 2 threads) and analytically, and the factorisation and solve of the
//! iteration matrices with the block elimination and with faer's sparse LU
//! (COLAMD), side by side. Results: docs/performance.md.
//!
//! `cargo bench -p quakejoint-model --bench paper`

use std::hint::black_box;
use std::path::PathBuf;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use quakejoint_model::generator::{build, Drive};
use quakejoint_model::run::{integrator_options, load_records};
use quakejoint_model::Config;
use quakejoint_solver::fd::{jacobian_with, Colouring};
use quakejoint_solver::integrator::radau5::{form_complex, form_real};
use quakejoint_solver::linalg::faer_lu::FaerPattern;
use quakejoint_solver::linalg::scalar::Complex64;
use quakejoint_solver::linalg::{FaerCache, KktSolver, LinearSolver};
use quakejoint_solver::{Assembly, AssemblyOptions, Observer, Radau5, StepView, TimeSeries};

struct State {
    asm: Arc<Assembly>,
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    lam: Vec<f64>,
}

struct Until(f64);

impl Observer for Until {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        view.t < self.0
    }
}

/// The paper model 3 s into Corralitos 090 (strong motion, bearings sliding).
fn state() -> State {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let config = Config::from_file(&dir.join("paper.toml")).unwrap();
    let rx = load_records(&config, &dir).unwrap().0.record;
    let gx = TimeSeries::uniform(0.0, rx.dt, rx.acceleration.clone()).unwrap();
    let model = build(&config, None, Drive::Earthquake { x: gx, y: None }).unwrap();
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default()).unwrap());
    let mut sim = Radau5::new(asm.clone(), integrator_options(&config)).unwrap();
    sim.run(3.0, &mut Until(3.0)).unwrap();
    State {
        t: sim.time(),
        q: sim.positions().to_vec(),
        v: sim.velocities().to_vec(),
        lam: sim.multipliers().to_vec(),
        asm,
    }
}

fn benches(c: &mut Criterion) {
    let s = state();
    let asm = &s.asm;
    let mut ws = asm.workspace();
    let mut g = c.benchmark_group("paper");
    g.sample_size(20);
    g.bench_function("residual", |b| b.iter(|| asm.residual(&mut ws, s.t, black_box(&s.q), &s.v, &s.lam)));
    let mut jac = asm.jacobian_values();
    g.bench_function("jacobian_analytic", |b| {
        b.iter(|| asm.jacobian(&mut ws, s.t, black_box(&s.q), &s.v, &s.lam, &mut jac))
    });
    let coloured = Colouring::new(asm);
    let dense = Colouring::dense(asm);
    let state = (s.t, &s.q[..], &s.v[..], &s.lam[..]);
    let mut fd = asm.jacobian_values();
    g.bench_function("jacobian_fd_coloured_serial", |b| {
        b.iter(|| jacobian_with(asm, &coloured, state, &mut fd, false, None))
    });
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        g.bench_function(format!("jacobian_fd_coloured_rayon_{threads}_threads"), |b| {
            b.iter(|| pool.install(|| jacobian_with(asm, &coloured, state, &mut fd, true, None)))
        });
    }
    g.sample_size(10);
    g.bench_function("jacobian_fd_dense", |b| b.iter(|| jacobian_with(asm, &dense, state, &mut fd, false, None)));
    g.sample_size(20);
    asm.jacobian(&mut ws, s.t, &s.q, &s.v, &s.lam, &mut jac);
    let sym = asm.block_structure();
    let h = 5e-3;
    let (gr, gc) = (3.6378 / h, Complex64::new(2.6811 / h, 3.0504 / h));
    let desc = |p: usize| format!("{p}");
    let mut cache = FaerCache::default();
    g.bench_function("symbolic_block", |b| {
        b.iter(|| Assembly::new(black_box(&build_paper()), &AssemblyOptions::default()).unwrap())
    });
    g.bench_function("symbolic_faer_colamd", |b| b.iter(|| FaerPattern::new(black_box(sym)).unwrap()));
    for (label, mode) in [("block", LinearSolver::Block), ("faer_colamd", LinearSolver::Faer)] {
        let mut real = KktSolver::<f64>::new(sym, mode);
        let mut cplx = KktSolver::<Complex64>::new(sym, mode);
        g.bench_function(format!("factor_real_{label}"), |b| {
            b.iter(|| real.factor(sym, &mut cache, &|o: &mut [f64]| form_real(asm, gr, &jac, o), &desc).unwrap())
        });
        g.bench_function(format!("factor_complex_{label}"), |b| {
            b.iter(|| {
                cplx.factor(sym, &mut cache, &|o: &mut [Complex64]| form_complex(asm, gc, &jac, o), &desc).unwrap()
            })
        });
        // the right-hand side is restored before every solve (solving in
        // place repeatedly would shrink it into subnormal numbers)
        let (rhs0, mut rhs) = (vec![1.0; sym.dim()], vec![0.0; sym.dim()]);
        g.bench_function(format!("solve_real_{label}"), |b| {
            b.iter(|| {
                rhs.copy_from_slice(&rhs0);
                real.solve(sym, &mut cache, black_box(&mut rhs)).unwrap()
            })
        });
        let (rhs0_c, mut rhs_c) = (vec![Complex64::new(1.0, 0.5); sym.dim()], vec![Complex64::default(); sym.dim()]);
        g.bench_function(format!("solve_complex_{label}"), |b| {
            b.iter(|| {
                rhs_c.copy_from_slice(&rhs0_c);
                cplx.solve(sym, &mut cache, black_box(&mut rhs_c)).unwrap()
            })
        });
    }
    g.finish();
    eprintln!(
        "paper model: {} coordinates, {} equations, {} unknowns, Jacobian nnz {}, colours {} (dF/dq nnz {}, density {:.3} %), block LU values {}, flops {}",
        asm.coordinates(),
        asm.equations(),
        asm.dim(),
        asm.jacobian_nnz(),
        coloured.colours(),
        coloured.nnz(),
        100.0 * coloured.nnz() as f64 / (asm.coordinates() as f64).powi(2),
        sym.nnz(),
        sym.flops()
    );
}

fn build_paper() -> quakejoint_solver::System {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs");
    let config = Config::from_file(&dir.join("paper.toml")).unwrap();
    build(&config, None, Drive::None).unwrap().system
}

criterion_group!(paper, benches);
criterion_main!(paper);
