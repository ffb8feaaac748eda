//! Kronecker products and column stacking, for solving Lyapunov equations `FᵀH + HF = −D` as
//! `(I ⊗ Fᵀ + Fᵀ ⊗ I) vec(H) = −vec(D)`.

use super::Matrix;
use crate::algebra::Ring;

/// The Kronecker product `A ⊗ B`.
pub fn kronecker<R: Ring>(a: &Matrix<R>, b: &Matrix<R>) -> Matrix<R> {
    let (p, q) = b.shape();
    Matrix::from_fn(a.rows() * p, a.cols() * q, |i, j| {
        a.get(i / p, j / q).clone() * b.get(i % p, j % q).clone()
    })
}

/// `vec(A)`: the columns of `A` stacked into one column.
pub fn vectorize<R: Ring>(a: &Matrix<R>) -> Matrix<R> {
    let (m, n) = a.shape();
    Matrix::from_fn(m * n, 1, |k, _| a.get(k % m, k / m).clone())
}

/// The inverse of [`vectorize`]: an `m`-row matrix from a stacked column.
pub fn unvectorize<R: Ring>(v: &Matrix<R>, m: usize) -> Matrix<R> {
    let n = v.rows().checked_div(m).unwrap_or(0);
    Matrix::from_fn(m, n, |i, j| v.get(j * m + i, 0).clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Rational;

    #[test]
    fn vec_of_a_product_is_a_kronecker_product() {
        // vec(A X B) = (Bᵀ ⊗ A) vec(X)
        let r = |x| Rational::from_i64(x);
        let a = Matrix::from_rows(vec![vec![r(1), r(2)], vec![r(3), r(4)]]).unwrap();
        let x = Matrix::from_rows(vec![vec![r(0), r(-1)], vec![r(5), r(2)]]).unwrap();
        let b = Matrix::from_rows(vec![vec![r(2), r(0)], vec![r(1), r(-3)]]).unwrap();
        let lhs = vectorize(&a.mul(&x).unwrap().mul(&b).unwrap());
        let rhs = kronecker(&b.transpose(), &a).mul(&vectorize(&x)).unwrap();
        assert_eq!(lhs, rhs);
        assert_eq!(unvectorize(&vectorize(&x), 2), x);
    }
}
