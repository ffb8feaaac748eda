//! The single-output observer gain by Ackermann's formula, exactly and fast: the formula
//! evaluated modulo many word-size primes and lifted back by Chinese remaindering (the
//! primitives live in [`crate::linalg::modular`]). The size of the work follows the size of the
//! gain, not that of `O_n⁻¹`, which has thousands of digits for n = 80.

use crate::algebra::{Field, Rational, Zero};
use crate::linalg::modular::{det_and_solve_mod, dot, int_mod, lift_cramer, IntMatrix};
use crate::linalg::Matrix;
use num_bigint::BigInt;

/// The single-output observer gain `K = P(A) O_n⁻¹ e_n` (A − KC), exact.
///
/// With `A`, `c` scaled to integers (`Ã = dA`, `c̃ = ec`) and `Q = f·d^n P(s/d)` integral,
/// `det(Õ)·Q(Ã) Õ⁻¹ e_n = Q(Ã)·adj(Õ) e_n` is an integer vector; it and `det Õ` are lifted
/// by Chinese remaindering up to Hadamard bounds (exact by construction), and
/// `K = e/(f d) · Q(Ã) Õ⁻¹ e_n`. `None` when `O_n` is singular (unobservable).
pub fn ackermann_gain_rational(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &[Rational],
) -> Option<Matrix<Rational>> {
    let n = a.rows();
    if n == 0 || c.rows() != 1 || c.cols() != n || desired.len() != n + 1 {
        return None;
    }
    let d = Rational::common_denominator(a.entries());
    let e = Rational::common_denominator(c.row(0));
    let at = IntMatrix::new(
        n,
        n,
        (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| a.get(j, i).scale_to_integer(&d))
            .collect(),
    );
    let ct = IntMatrix::new(
        1,
        n,
        c.row(0).iter().map(|x| x.scale_to_integer(&e)).collect(),
    );
    // P̃(s) = d^n P(s/d): coefficient k times d^(n−k); then cleared of denominators by f.
    let d_r = Rational::from(d.clone());
    let scaled: Vec<Rational> = (0..=n)
        .map(|k| desired[k].clone() * num_traits::pow(d_r.clone(), n - k))
        .collect();
    let f = Rational::common_denominator(&scaled);
    let q: Vec<BigInt> = scaled.iter().map(|x| x.scale_to_integer(&f)).collect();
    // Bounds: ‖c̃ Ã^k‖ ≤ ‖c̃‖ ‖Ã‖^k.
    let la = at.log2_norm();
    let lc = ct.log2_norm();
    let det_bits: f64 = (0..n).map(|k| lc + k as f64 * la).sum();
    let adj_bits: f64 = (0..n.saturating_sub(1))
        .map(|k| lc + k as f64 * la)
        .sum::<f64>()
        + 0.5 * (n as f64).log2();
    let poly_bits = q
        .iter()
        .enumerate()
        .map(|(k, x)| x.bits() as f64 + k as f64 * la)
        .fold(0.0f64, f64::max)
        + ((n + 1) as f64).log2();
    let bits = det_bits.max(adj_bits + poly_bits).ceil() as u64 + 2;
    let (det, y) = lift_cramer(n, bits, |p| gain_residues(&at, &ct, &q, n, p))?;
    if det.is_zero() {
        return None;
    }
    // K = e/(f d) · Y / det, one reduction per entry
    let denominator = f * d * &det;
    Some(Matrix::column(
        y.into_iter()
            .map(|v| crate::algebra::fraction(v * &e, denominator.clone()))
            .collect(),
    ))
}

/// `(det O mod p, (Q(Ã) O⁻¹ e_n) mod p)` for one prime.
fn gain_residues(
    at: &IntMatrix,
    ct: &IntMatrix,
    q: &[BigInt],
    n: usize,
    p: u64,
) -> Option<(u64, Vec<u64>)> {
    {
        let atp = at.residues(p); // row j of Aᵀ is column j of A
        let cp = ct.residues(p);
        // O mod p, rows c̃, c̃Ã, …: (rÃ)_j = r · (column j of Ã)
        let mut o = Vec::with_capacity(n * n);
        o.extend_from_slice(&cp);
        for r in 1..n {
            let last = o[(r - 1) * n..r * n].to_vec();
            for j in 0..n {
                o.push(dot(&last, &atp[j * n..(j + 1) * n], p));
            }
        }
        let mut en = vec![0u64; n];
        en[n - 1] = 1;
        let (det, qn) = det_and_solve_mod(o, n, en, 1, p)?;
        // Horner with Ã: acc ← Ã acc + q_k qn; Ã acc needs rows of Ã = columns of Aᵀ.
        let a_rows: Vec<u64> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| atp[j * n + i])
            .collect();
        let qp: Vec<u64> = q.iter().map(|x| int_mod(x, p)).collect();
        let mut acc = vec![0u64; n];
        for &qk in qp.iter().rev() {
            acc = (0..n)
                .map(|i| (dot(&a_rows[i * n..(i + 1) * n], &acc, p) + qk * qn[i]) % p)
                .collect();
        }
        Some((det, acc))
    }
}
