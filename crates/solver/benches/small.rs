//! The small fixed-size kernels (`linalg::small`) against nalgebra's
//! stack-allocated matrices, on the shapes the reference run uses most:
//! the 3 x 3 solve of a bearing's local friction problem (nalgebra: LU with
//! partial pivoting), and the block products `y -= A x` of the block
//! elimination's solves for a bearing (3 x 3 diagonal, 6 x 3 and 3 x 6 to
//! its support beam), real and complex. Each iteration runs the kernel over
//! 270 independent inputs (the reference joint's bearings), so the numbers
//! are per 270 calls. Results: docs/performance.md, "Small kernels".

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Complex, Matrix3, SMatrix, SMatrixView, SVector, Vector3};
use quakejoint_solver::linalg::scalar::Complex64;
use quakejoint_solver::linalg::small::{gemv_sub_fixed, solve3, solve3_adjugate};

const BEARINGS: usize = 270;

/// Deterministic, well-conditioned inputs.
fn value(i: usize, j: usize) -> f64 {
    let x = ((i * 7919 + j * 104_729) % 1000) as f64 / 1000.0;
    if i % 4 == j % 4 {
        4.0 + x
    } else {
        x - 0.5
    }
}

fn systems() -> Vec<([[f64; 3]; 3], [f64; 3])> {
    (0..BEARINGS)
        .map(|k| {
            let a = [0, 1, 2].map(|r| [0, 1, 2].map(|c| value(k + r, k + c) + if r == c { 4.0 } else { 0.0 }));
            (a, [value(k, 1), value(k, 2), value(k, 3)])
        })
        .collect()
}

fn solve(c: &mut Criterion) {
    let sys = systems();
    let mut g = c.benchmark_group("solve 3x3 (270)");
    g.bench_function("linalg::small::solve3 (hand-written)", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for (a, r) in &sys {
                s += solve3(black_box(*a), black_box(*r)).unwrap()[0];
            }
            s
        })
    });
    g.bench_function("linalg::small::solve3_adjugate (hand-written)", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for (a, r) in &sys {
                s += solve3_adjugate(black_box(*a), black_box(*r)).unwrap()[0];
            }
            s
        })
    });
    let nsys: Vec<(Matrix3<f64>, Vector3<f64>)> =
        sys.iter().map(|(a, r)| (Matrix3::from_fn(|i, j| a[i][j]), Vector3::new(r[0], r[1], r[2]))).collect();
    g.bench_function("nalgebra LU", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for (a, r) in &nsys {
                s += black_box(*a).lu().solve(&black_box(*r)).unwrap()[0];
            }
            s
        })
    });
    g.finish();
}

fn gemv<const R: usize, const C: usize>(c: &mut Criterion) {
    let a: Vec<Vec<f64>> = (0..BEARINGS).map(|k| (0..R * C).map(|i| value(k, i)).collect()).collect();
    let x: Vec<Vec<f64>> = (0..BEARINGS).map(|k| (0..C).map(|i| value(i, k)).collect()).collect();
    let mut g = c.benchmark_group(format!("y -= A x, {R} x {C} (270)"));
    g.bench_function("hand-written, real", |b| {
        let mut y = vec![0.0; R];
        b.iter(|| {
            for (a, x) in a.iter().zip(&x) {
                gemv_sub_fixed::<f64, R, C>(&mut y, black_box(a), black_box(x));
            }
            y[0]
        })
    });
    let na: Vec<SMatrix<f64, R, C>> = a.iter().map(|a| SMatrix::from_fn(|i, j| a[i * C + j])).collect();
    let nx: Vec<SVector<f64, C>> = x.iter().map(|x| SVector::from_fn(|i, _| x[i])).collect();
    g.bench_function("nalgebra, real", |b| {
        let mut y = SVector::<f64, R>::zeros();
        b.iter(|| {
            for (a, x) in na.iter().zip(&nx) {
                y -= black_box(a) * black_box(x);
            }
            y[0]
        })
    });
    // the blocks as the block elimination stores them (row-major), viewed
    // in place as the transpose of a column-major C x R matrix
    g.bench_function("nalgebra, real, row-major view", |b| {
        let mut y = SVector::<f64, R>::zeros();
        b.iter(|| {
            for (a, x) in a.iter().zip(&nx) {
                let at = SMatrixView::<f64, C, R>::from_slice(black_box(a));
                y.gemv_tr(-1.0, &at, black_box(x), 1.0);
            }
            y[0]
        })
    });
    let ca: Vec<Vec<Complex64>> = a.iter().map(|a| a.iter().map(|&v| Complex64::new(v, 0.5 * v)).collect()).collect();
    let cx: Vec<Vec<Complex64>> = x.iter().map(|x| x.iter().map(|&v| Complex64::new(v, -v)).collect()).collect();
    g.bench_function("hand-written, complex", |b| {
        let mut y = vec![Complex64::new(0.0, 0.0); R];
        b.iter(|| {
            for (a, x) in ca.iter().zip(&cx) {
                gemv_sub_fixed::<Complex64, R, C>(&mut y, black_box(a), black_box(x));
            }
            y[0]
        })
    });
    let nca: Vec<SMatrix<Complex<f64>, R, C>> = ca.iter().map(|a| SMatrix::from_fn(|i, j| a[i * C + j])).collect();
    let ncx: Vec<SVector<Complex<f64>, C>> = cx.iter().map(|x| SVector::from_fn(|i, _| x[i])).collect();
    g.bench_function("nalgebra, complex", |b| {
        let mut y = SVector::<Complex<f64>, R>::zeros();
        b.iter(|| {
            for (a, x) in nca.iter().zip(&ncx) {
                y -= black_box(a) * black_box(x);
            }
            y[0]
        })
    });
    g.finish();
}

fn kernels(c: &mut Criterion) {
    solve(c);
    gemv::<3, 3>(c);
    gemv::<6, 3>(c);
    gemv::<3, 6>(c);
}

criterion_group!(benches, kernels);
criterion_main!(benches);
