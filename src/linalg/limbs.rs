//! `Q(A)·Y` by Horner's rule for a matrix `A` of machine-word integers and big integers `Y`, on
//! fixed-width two's complement limbs: the inner loop of every exact gain (`K = P(A)·q_n`).
//!
//! **Algorithm.** Horner's rule, `acc ← A·acc + q_j·Y` for `j = deg, …, 0`. A bound on every
//! value the loop will hold is found first (below), and each integer is stored in that many
//! 32-bit limbs, two's complement. An entry of `A·acc` is summed limb column by limb column: for
//! limb `l < w − 1` the terms `a_t·x_t[l]` with `a_t ≥ 0` go to one `u64` and the others (as
//! `|a_t|·x_t[l]`) to a second; the top limb, read as signed, goes to an `i64`. Limbs of 32 bits
//! keep every product a machine multiplication in WebAssembly too, which has no 64 × 64 → 128-bit
//! one. One carry pass
//! turns the columns into limbs. Nothing is allocated and nothing is normalised inside the loop,
//! where num-bigint allocates a product per term.
//!
//! **Identity.** With `x_t = Σ_(l<w−1) x_t[l]·2^(32l) + s_t·2^(32(w−1))` (`s_t` the top limb as
//! a signed word), `Σ_t a_t x_t = Σ_l 2^(32l) · Σ_t a_t x_t[l]`: the columns are independent
//! and are carried once at the end.
//!
//! **Bound.** `|A·x|∞ ≤ ‖A‖∞·|x|∞` with `‖A‖∞` the largest row sum of `|a|`, so with
//! `‖A‖∞ < 2^α`, `|q_j| < 2^(β_j)` and `|Y| < 2^γ`, every value after the step for `q_j` is
//! below `2^(b_j)`, `b_j = max(b_(j+1) + α, β_j + γ) + 1`; the last `b` gives the width. The
//! row sums are kept below `2^29` (and a coefficient used as a multiplier below `2^29`), so a
//! column sum stays below `2^62`. A value that would leave the width anyway is detected in the
//! carry pass and the caller takes num-bigint's path.
//!
//! **Cost.** `(deg + 1)·n²·w` word products for `n × n` `A` and `w` limbs, plus one conversion
//! of `Y` in and of the result out.

use crate::algebra::words::negate_limbs;
use crate::algebra::BigInt;
use num_bigint::{BigUint, Sign};
use num_traits::{Signed, ToPrimitive, Zero};

/// Below this, a row sum of `|a|` or a coefficient keeps every column sum below `2^62`.
const WORD_LIMIT: u64 = 1 << 29;

/// `n·k` integers of `width` 32-bit limbs each, two's complement, least significant limb first.
struct Limbs {
    width: usize,
    data: Vec<u32>,
}

impl Limbs {
    fn zeros(len: usize, width: usize) -> Self {
        Limbs {
            width,
            data: vec![0; len * width],
        }
    }

    /// The integers, `None` when one needs more than `32·width − 1` bits of magnitude.
    fn from_bigints<'a>(
        values: impl ExactSizeIterator<Item = &'a BigInt>,
        width: usize,
    ) -> Option<Self> {
        let mut out = Limbs::zeros(values.len(), width);
        for (i, x) in values.enumerate() {
            if x.bits() + 1 > 32 * width as u64 {
                return None;
            }
            let cell = &mut out.data[i * width..(i + 1) * width];
            for (limb, digit) in cell.iter_mut().zip(x.iter_u32_digits()) {
                *limb = digit;
            }
            if x.is_negative() {
                negate_limbs(cell);
            }
        }
        Some(out)
    }

    fn cell(&self, i: usize) -> &[u32] {
        &self.data[i * self.width..(i + 1) * self.width]
    }

    fn to_bigints(&self) -> Vec<BigInt> {
        (0..self.data.len() / self.width)
            .map(|i| {
                let mut cell = self.cell(i).to_vec();
                let negative = cell.last().is_some_and(|&top| (top as i32) < 0);
                if negative {
                    negate_limbs(&mut cell);
                }
                let sign = if negative { Sign::Minus } else { Sign::Plus };
                BigInt::from_biguint(sign, BigUint::new(cell))
            })
            .collect()
    }
}

/// One entry `Σ_t m_t·x_t` as limb columns: `pos`/`neg` for the limbs below the top, `top` for
/// the top limb read as signed.
struct Columns {
    pos: Vec<u64>,
    neg: Vec<u64>,
    top: i64,
}

impl Columns {
    fn new(width: usize) -> Self {
        Columns {
            pos: vec![0; width - 1],
            neg: vec![0; width - 1],
            top: 0,
        }
    }

    /// `self += m·x` for one integer `x` in limbs (not inlined: one copy of the loop for its
    /// three callers keeps the browser module small, and a call per w-limb pass costs nothing).
    #[inline(never)]
    fn add(&mut self, m: i64, x: &[u32]) {
        let (low, top) = x.split_at(x.len() - 1);
        let side = if m >= 0 { &mut self.pos } else { &mut self.neg };
        // |m| < 2^29 (the module's bound): as a 32-bit word the product is one 32 × 32 → 64-bit
        // multiply, two to a vector instruction, where a 64-bit factor takes three
        debug_assert!(m.unsigned_abs() < WORD_LIMIT);
        let factor = m.unsigned_abs() as u32;
        for (column, &limb) in side.iter_mut().zip(low) {
            *column += u64::from(factor) * u64::from(limb);
        }
        self.top += m * i64::from(top[0] as i32);
    }

    /// The carried limbs written to `out`, the columns cleared; `false` when the value does not
    /// fit the width (never, under the module's bound).
    fn carry_into(&mut self, out: &mut [u32]) -> bool {
        let mut carry: i64 = 0;
        for ((limb, p), n) in out
            .iter_mut()
            .zip(self.pos.iter_mut())
            .zip(self.neg.iter_mut())
        {
            // p, n < 2^62: the difference and the carry fit an i64
            let v = (*p as i64) - (*n as i64) + carry;
            *limb = v as u32;
            carry = v >> 32;
            *p = 0;
            *n = 0;
        }
        let v = self.top + carry;
        self.top = 0;
        match i32::try_from(v) {
            Ok(top) => {
                if let Some(last) = out.last_mut() {
                    *last = top as u32;
                }
                true
            }
            Err(_) => false,
        }
    }
}

/// The term `q_j·Y` of one Horner step.
enum Term {
    Zero,
    /// `q_j` a word below `2^29`: multiplied in the column sums.
    Word(i64),
    /// `q_j` long: `q_j·Y` formed once on num-bigint.
    Long(Limbs),
}

impl Term {
    fn new(qj: &BigInt, y: &[BigInt], width: usize) -> Option<Self> {
        if qj.is_zero() {
            return Some(Term::Zero);
        }
        match qj.to_i64().filter(|m| m.unsigned_abs() < WORD_LIMIT) {
            Some(m) => Some(Term::Word(m)),
            None => {
                let products: Vec<BigInt> = y.iter().map(|v| v * qj).collect();
                Limbs::from_bigints(products.iter(), width).map(Term::Long)
            }
        }
    }
}

/// `Q(A)·Y = Σ_j q_j A^j Y` for the `n × n` matrix `a` (row-major machine words) and the `n × k`
/// integer matrix `y` (row-major), `q` lowest power first. `None` when `A`'s row sums are not
/// below `2^29` (the caller multiplies on num-bigint instead).
pub(crate) fn horner(
    a: &[i64],
    n: usize,
    q: &[BigInt],
    y: &[BigInt],
    k: usize,
) -> Option<Vec<BigInt>> {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(y.len(), n * k);
    let norm = (0..n)
        .map(|i| {
            a[i * n..(i + 1) * n]
                .iter()
                .map(|x| u128::from(x.unsigned_abs()))
                .sum::<u128>()
        })
        .max()
        .unwrap_or(0);
    if norm >= u128::from(WORD_LIMIT) {
        return None;
    }
    // the bound: every value below 2^bits
    let alpha = u64::from(128 - norm.leading_zeros());
    let gamma = y.iter().map(BigInt::bits).max().unwrap_or(0);
    let mut bits: Option<u64> = None;
    for qj in q.iter().rev() {
        let from_acc = bits.map(|b| b + alpha);
        let from_y = (!qj.is_zero() && gamma > 0).then(|| qj.bits() + gamma);
        bits = from_acc.max(from_y).map(|b| b + 1);
    }
    let Some(bits) = bits else {
        return Some(vec![BigInt::zero(); n * k]);
    };
    let width = usize::try_from(bits / 32 + 1).ok()?;
    let y_limbs = Limbs::from_bigints(y.iter(), width)?;
    let mut acc = Limbs::zeros(n * k, width);
    let mut next = Limbs::zeros(n * k, width);
    let mut columns = Columns::new(width);
    let mut started = false;
    for qj in q.iter().rev() {
        if !started && qj.is_zero() {
            continue;
        }
        let term = Term::new(qj, y, width)?;
        for i in 0..n {
            for c in 0..k {
                if started {
                    for (t, &m) in a[i * n..(i + 1) * n].iter().enumerate() {
                        if m != 0 {
                            columns.add(m, acc.cell(t * k + c));
                        }
                    }
                }
                match &term {
                    Term::Zero => {}
                    Term::Word(m) => columns.add(*m, y_limbs.cell(i * k + c)),
                    Term::Long(z) => columns.add(1, z.cell(i * k + c)),
                }
                let w = next.width;
                if !columns.carry_into(&mut next.data[(i * k + c) * w..(i * k + c + 1) * w]) {
                    return None;
                }
            }
        }
        std::mem::swap(&mut acc, &mut next);
        started = true;
    }
    Some(acc.to_bigints())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Horner on num-bigint, the oracle.
    fn reference(a: &[i64], n: usize, q: &[BigInt], y: &[BigInt], k: usize) -> Vec<BigInt> {
        let mut acc = vec![BigInt::zero(); n * k];
        for qj in q.iter().rev() {
            let mut next = vec![BigInt::zero(); n * k];
            for i in 0..n {
                for c in 0..k {
                    let mut s = qj * &y[i * k + c];
                    for t in 0..n {
                        s += &acc[t * k + c] * a[i * n + t];
                    }
                    next[i * k + c] = s;
                }
            }
            acc = next;
        }
        acc
    }

    fn big(digits: &[i64], shift: u32) -> BigInt {
        digits
            .iter()
            .fold(BigInt::zero(), |acc, &d| (acc << shift) + BigInt::from(d))
    }

    #[test]
    fn limbs_round_trip_signs_and_widths() {
        let values = [
            BigInt::zero(),
            BigInt::from(-1),
            BigInt::from(i64::MIN),
            BigInt::from(u64::MAX),
            -(BigInt::from(u64::MAX)),
            (BigInt::from(1) << 190u32) - 1,
            -(BigInt::from(1) << 190u32),
        ];
        let limbs = Limbs::from_bigints(values.iter(), 8).expect("fits 255 bits");
        assert_eq!(limbs.to_bigints(), values);
        // 2^191 needs 192 bits and a sign: not in six limbs
        assert!(Limbs::from_bigints([BigInt::from(1) << 191u32].iter(), 6).is_none());
    }

    #[test]
    fn a_row_sum_at_the_limit_is_refused() {
        let q = [BigInt::from(1), BigInt::from(1)];
        let y = [BigInt::from(1)];
        assert_eq!(
            horner(&[(1 << 29) - 1], 1, &q, &y, 1),
            Some(reference(&[(1 << 29) - 1], 1, &q, &y, 1))
        );
        assert!(horner(&[1 << 29], 1, &q, &y, 1).is_none());
        assert!(horner(&[i64::MIN], 1, &q, &y, 1).is_none());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        #[test]
        fn agrees_with_num_bigint(
            n in 1usize..6,
            k in 1usize..3,
            seed in proptest::collection::vec(-1_000_000_000_i64..1_000_000_000, 64),
            shift in 0u32..90,
            deg in 0usize..8,
            extreme in any::<bool>(),
        ) {
            let pick = |i: usize| seed[i % seed.len()];
            let a: Vec<i64> = (0..n * n)
                .map(|i| if extreme && i % 3 == 0 { (1 << 27) * pick(i).signum() } else { pick(i) % 20 })
                .collect();
            let y: Vec<BigInt> = (0..n * k).map(|i| big(&[pick(i + 7), pick(i + 11)], shift)).collect();
            let q: Vec<BigInt> = (0..=deg)
                .map(|j| if j % 3 == 1 { big(&[pick(j + 3), pick(j + 5), pick(j)], 64) } else { BigInt::from(pick(j + 13) % 7) })
                .collect();
            let got = horner(&a, n, &q, &y, k);
            prop_assert_eq!(got, Some(reference(&a, n, &q, &y, k)));
        }
    }
}
