//! The `f64` side, through nalgebra: conversion, eigenvalues, singular values, condition numbers,
//! rank with an explicit tolerance.

use super::Matrix;
use crate::algebra::{Ring, ToF64};
use nalgebra::{linalg::Schur, Complex, DMatrix};

/// The nearest `f64` matrix, as an nalgebra `DMatrix`.
pub fn to_nalgebra<T: Ring + ToF64>(a: &Matrix<T>) -> DMatrix<f64> {
    DMatrix::from_fn(a.rows(), a.cols(), |i, j| a.get(i, j).to_f64())
}

/// An nalgebra matrix as a workbench matrix.
pub fn from_nalgebra(a: &DMatrix<f64>) -> Matrix<f64> {
    Matrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// The largest of non-negative values, NaN when any is NaN: a NaN never passes for small (a
/// plain `fold(0.0, f64::max)` skips it). 0 for none.
pub fn max_or_nan(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |acc, x| {
        if acc.is_nan() || x.is_nan() {
            f64::NAN
        } else {
            acc.max(x)
        }
    })
}

/// The spectral radius max |λ|, NaN when an eigenvalue cannot be computed (see
/// [`eigenvalues`]).
pub fn spectral_radius(a: &DMatrix<f64>) -> f64 {
    max_or_nan(eigenvalues(a).iter().map(|z| z.norm()))
}

/// The eigenvalues (real Schur form), sorted by real part then imaginary part.
///
/// The QR iteration is bounded (LAPACK's 30 sweeps per eigenvalue); when it does not converge
/// the matrix is balanced (Parlett–Reinsch, a diagonal similarity) and tried once more. A matrix
/// whose eigenvalues still cannot be computed — or one with infinite or NaN entries — gives NaN
/// eigenvalues, which every comparison downstream treats as "not verified", never as a hang.
pub fn eigenvalues(a: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let n = a.nrows();
    if n == 0 || n != a.ncols() {
        return Vec::new();
    }
    let unknown = vec![Complex::new(f64::NAN, f64::NAN); n];
    if a.iter().any(|x| !x.is_finite()) {
        return unknown;
    }
    let budget = 30 * n.max(10);
    let schur = |m: DMatrix<f64>| Schur::try_new(m, f64::EPSILON, budget);
    let found = schur(a.clone()).or_else(|| {
        let mut balanced = a.clone();
        if balanced.amax() < 1e150 {
            nalgebra::linalg::balancing::balance_parlett_reinsch(&mut balanced);
        }
        schur(balanced)
    });
    let Some(s) = found else {
        return unknown;
    };
    let mut ev: Vec<Complex<f64>> = s.complex_eigenvalues().iter().copied().collect();
    ev.sort_by(|x, y| x.re.total_cmp(&y.re).then(x.im.total_cmp(&y.im)));
    ev
}

/// The singular value decomposition, sorted (largest first), or `None` when it cannot be
/// computed: an entry that is infinite or NaN, singular values that overflow, or the
/// iteration not converging within its bound. nalgebra's `svd` panics ("Singular value was
/// NaN") or iterates without bound in those cases; this never does.
pub fn try_svd(
    a: &DMatrix<f64>,
    compute_u: bool,
    compute_v: bool,
) -> Option<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let budget = 100 * a.nrows().max(a.ncols()).max(10);
    let mut svd = a
        .clone()
        .try_svd_unordered(compute_u, compute_v, f64::EPSILON, budget)?;
    if svd.singular_values.iter().any(|x| !x.is_finite()) {
        return None;
    }
    svd.sort_by_singular_values();
    Some(svd)
}

/// Singular values, largest first; NaN values when they cannot be computed (see [`try_svd`]).
pub fn singular_values(a: &DMatrix<f64>) -> Vec<f64> {
    // scaled to unit largest entry, so that no intermediate overflows
    let scale = a.amax();
    if !(scale.is_finite()) {
        return vec![f64::NAN; a.nrows().min(a.ncols())];
    }
    if scale == 0.0 {
        return vec![0.0; a.nrows().min(a.ncols())];
    }
    match try_svd(&(a / scale), false, false) {
        Some(svd) => svd.singular_values.iter().map(|x| x * scale).collect(),
        None => vec![f64::NAN; a.nrows().min(a.ncols())],
    }
}

/// The 2-norm condition number `σ_max / σ_min` (infinite when singular).
pub fn condition_number(a: &DMatrix<f64>) -> f64 {
    let s = singular_values(a);
    match (s.first(), s.last()) {
        (Some(&hi), _) if hi.is_nan() => f64::NAN,
        (Some(&hi), Some(&lo)) if lo > 0.0 => hi / lo,
        _ => f64::INFINITY,
    }
}

/// The numerical rank: singular values above `tolerance · σ_max`.
pub fn rank(a: &DMatrix<f64>, tolerance: f64) -> usize {
    let s = singular_values(a);
    let top = s.first().copied().unwrap_or(0.0);
    s.iter().filter(|&&x| x > tolerance * top).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_the_stoustrup_plant() {
        let a = DMatrix::from_row_slice(2, 2, &[2.0, -3.0, 4.0, -5.0]);
        let ev = eigenvalues(&a);
        assert!((ev[0].re + 2.0).abs() < 1e-12 && (ev[1].re + 1.0).abs() < 1e-12);
        assert!(condition_number(&DMatrix::<f64>::identity(3, 3)) - 1.0 < 1e-15);
        assert_eq!(
            rank(&DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]), 1e-12),
            1
        );
    }
}
