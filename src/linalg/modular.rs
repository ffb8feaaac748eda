//! Multimodular exact linear algebra over the rationals.
//!
//! Large exact problems are solved modulo many word-size primes and lifted back:
//!
//! * the characteristic polynomial of an integer matrix, by Hessenberg reduction mod p (O(n³)
//!   per prime) and Chinese remaindering up to a Hadamard-type bound on the coefficients, so
//!   the result is exact by construction;
//! * linear systems (and, in [`crate::observer`], single-output observer gains), whose size is not known in advance: residues are
//!   accumulated until rational reconstruction gives the same answer twice (output-sensitive),
//!   and the answer is then *certified* exactly (`A·x = b`, or `det(sI − (A − KC)) = P(s)`), so a
//!   wrong reconstruction can never be returned.
//!
//! The cost is governed by the size of the answer, not by the size of intermediate values such
//! as `O_n⁻¹` (thousands of digits for n = 80), which is what makes the exact gain fast.

use super::Matrix;
use crate::algebra::{Field, One, Rational, Zero};
use num_bigint::BigInt;
use num_traits::ToPrimitive;

/// Primes below 2³¹, largest first (products of two residues fit in a `u64`): the first
/// [`TABLED`] from a table computed when the program is compiled, the rest generated as they
/// are taken — there are about 10⁸ of them, so the supply never runs out before a bound is
/// reached. A generated prime costs about ten Miller–Rabin tests of odd candidates (≈ 1.5 µs),
/// far below the O(n³) work done modulo it; but a 10-state design takes its first primes
/// several times over (one search per multimodular step), about 5 % of its work before the
/// tables. (A table of the first 4 096 built once per process cost 5–7 ms before the first
/// command could use one, most of the time of a 10-state `owb observe`.)
pub(crate) fn primes() -> impl Iterator<Item = u64> {
    primes_after(&PRIMES_BELOW_2_31)
}

/// The primes the eliminations of [`lift_cramer`] and [`determinant_rational`] run modulo:
/// below 2³⁰ rather than 2³¹, so that an entry takes sixteen products (each below 2⁶⁰) between
/// two reductions instead of three — the reduction passes were about 40 % of the eliminations'
/// time at order 40 — for 3 % more primes.
fn elimination_primes() -> impl Iterator<Item = u64> {
    primes_after(&PRIMES_BELOW_2_30)
}

/// How many primes each table holds: what the multimodular steps of systems of order up to
/// about 20 take, at 256 bytes a table.
const TABLED: usize = 64;

/// The [`TABLED`] largest primes below 2³¹, largest first.
static PRIMES_BELOW_2_31: [u32; TABLED] = largest_primes_below(1 << 31);

/// The [`TABLED`] largest primes below 2³⁰, largest first.
static PRIMES_BELOW_2_30: [u32; TABLED] = largest_primes_below(1 << 30);

/// The [`TABLED`] largest primes below `bound` (an even number), largest first: evaluated by
/// the compiler.
const fn largest_primes_below(bound: u64) -> [u32; TABLED] {
    let mut table = [0u32; TABLED];
    let (mut found, mut candidate) = (0, bound - 1);
    while found < TABLED {
        if is_prime(candidate) {
            table[found] = candidate as u32;
            found += 1;
        }
        candidate -= 2;
    }
    table
}

/// A table's primes, then the primes below its last one, generated: every prime below the
/// table's bound, largest first.
fn primes_after(table: &'static [u32; TABLED]) -> impl Iterator<Item = u64> {
    let last = u64::from(table[TABLED - 1]);
    table.iter().map(|&p| u64::from(p)).chain(
        (1..last / 2)
            .rev()
            .map(|k| 2 * k + 1)
            .filter(|&c| is_prime(c)),
    )
}

/// Deterministic Miller–Rabin for n < 2³² (bases 2, 7, 61); a `const fn`, so that the prime
/// tables are computed by the compiler (plain `%` products: Barrett's are not `const`).
const fn is_prime(n: u64) -> bool {
    debug_assert!(n < 1 << 32);
    if n < 2 {
        return false;
    }
    let small = [2u64, 3, 5, 7, 11, 13];
    let mut i = 0;
    while i < small.len() {
        if n.is_multiple_of(small[i]) {
            return n == small[i];
        }
        i += 1;
    }
    let mut d = n - 1;
    let mut s = 0;
    while d.is_multiple_of(2) {
        d /= 2;
        s += 1;
    }
    let witnesses = [2u64, 7, 61];
    let mut w = 0;
    'witness: while w < witnesses.len() {
        let a = witnesses[w];
        w += 1;
        if a.is_multiple_of(n) {
            continue;
        }
        // a^d mod n by squaring
        let (mut base, mut e, mut x) = (a % n, d, 1u64);
        while e > 0 {
            if e & 1 == 1 {
                x = x * base % n;
            }
            base = base * base % n;
            e >>= 1;
        }
        if x == 1 || x == n - 1 {
            continue;
        }
        let mut r = 1;
        while r < s {
            x = x * x % n;
            if x == n - 1 {
                continue 'witness;
            }
            r += 1;
        }
        return false;
    }
    true
}

/// Barrett reduction for a fixed prime p < 2³¹: `x mod p` for `x < 2⁶²` with one high
/// multiplication instead of a division.
#[derive(Clone, Copy)]
struct Barrett {
    p: u64,
    m: u64,
}

impl Barrett {
    fn new(p: u64) -> Self {
        Barrett {
            p,
            m: ((1u128 << 64) / p as u128) as u64,
        }
    }
    #[inline(always)]
    fn reduce(self, x: u64) -> u64 {
        let q = (crate::algebra::words::wide_mul(x, self.m) >> 64) as u64;
        let r = x - q * self.p;
        if r >= self.p {
            r - self.p
        } else {
            r
        }
    }
    #[inline(always)]
    fn mul(self, a: u64, b: u64) -> u64 {
        self.reduce(a * b)
    }
}

/// `b^e mod p` by squaring, with Barrett's products (the eliminations invert a pivot this way,
/// n per prime: sixty divisions each otherwise).
fn pow_mod(b: u64, mut e: u64, p: u64) -> u64 {
    let br = Barrett::new(p);
    let (mut b, mut r) = (b % p, 1 % p);
    while e > 0 {
        if e & 1 == 1 {
            r = br.mul(r, b);
        }
        b = br.mul(b, b);
        e >>= 1;
    }
    r
}

pub(crate) fn inv_mod(a: u64, p: u64) -> Option<u64> {
    (!a.is_multiple_of(p)).then(|| pow_mod(a, p - 2, p))
}

/// `x mod p` in `0..p` for a prime of [`primes`] (below 2³¹): Horner over the magnitude's
/// 32-bit halves from the most significant, each step `(r · 2³² + half) mod p` in one `u64`
/// division (no allocation: num-bigint's `BigInt % u64` goes through its general long
/// division, and a `u128` remainder through a software routine; either dominated the
/// multimodular paths on large entries).
pub(crate) fn int_mod(x: &BigInt, p: u64) -> u64 {
    debug_assert!(p < 1 << 32);
    residue(
        x.sign() == num_bigint::Sign::Minus,
        x.magnitude().iter_u32_digits().rev(),
        Barrett::new(p),
    )
}

/// `±digits mod p` for 32-bit digits, most significant first: each step `(r·2³² + d) mod p`
/// stays below `2⁶⁴` for `p < 2³²`, so Barrett's reduction takes it, with no division.
#[inline]
fn residue(negative: bool, digits: impl Iterator<Item = u32>, br: Barrett) -> u64 {
    let r = digits.fold(0u64, |r, d| br.reduce((r << 32) | u64::from(d)));
    if r != 0 && negative {
        br.p - r
    } else {
        r
    }
}

/// Characteristic polynomial mod p (coefficients ascending, monic) by Hessenberg reduction.
fn charpoly_mod(mut h: Vec<Vec<u64>>, p: u64) -> Vec<u64> {
    let n = h.len();
    let br = Barrett::new(p);
    for m in 1..n {
        let Some(piv) = (m..n).find(|&i| h[i][m - 1] != 0) else {
            continue;
        };
        if piv != m {
            h.swap(piv, m);
            for row in h.iter_mut() {
                row.swap(piv, m);
            }
        }
        let inv = inv_mod(h[m][m - 1], p).expect("nonzero pivot");
        for i in m + 1..n {
            let u = br.mul(h[i][m - 1], inv);
            if u == 0 {
                continue;
            }
            // row_i −= u · row_m
            let (top, bottom) = h.split_at_mut(i);
            let (row_m, row_i) = (&top[m], &mut bottom[0]);
            let neg_u = p - u;
            for j in m - 1..n {
                row_i[j] = br.reduce(row_i[j] + neg_u * row_m[j]);
            }
            // col_m += u · col_i
            for row in h.iter_mut() {
                row[m] = br.reduce(row[m] + u * row[i]);
            }
        }
    }
    // p_m = (x − h_mm) p_{m−1} − Σ_i h_{m−i,m} (Π h_{j,j−1}) p_{m−i−1}   (1-indexed)
    let mut polys: Vec<Vec<u64>> = vec![vec![1]];
    for m in 1..=n {
        let prev = &polys[m - 1];
        let mut next = vec![0u64; m + 1];
        let neg_h = p - h[m - 1][m - 1];
        for (k, &c) in prev.iter().enumerate() {
            next[k + 1] = br.reduce(next[k + 1] + c);
            next[k] = br.reduce(next[k] + neg_h * c);
        }
        let mut t = 1u64;
        for i in 1..m {
            t = br.mul(t, h[m - i][m - i - 1]);
            if t == 0 {
                break;
            }
            let coef = br.mul(h[m - i - 1][m - 1], t);
            if coef == 0 {
                continue;
            }
            let neg = p - coef;
            for (k, &c) in polys[m - i - 1].iter().enumerate() {
                next[k] = br.reduce(next[k] + neg * c);
            }
        }
        polys.push(next);
    }
    polys.pop().unwrap_or_default()
}

/// Chinese remaindering of a vector of residues, by Garner's mixed-radix algorithm.
///
/// Residues are only stored while primes are added; the integers are built once, at the end:
/// the mixed-radix digits of each value come from word-size dot products (one reduction per
/// digit), and the value from them by Horner with word-size multipliers. No big-integer
/// remainder is ever taken, which incremental remaindering needs once per value and prime.
struct Crt {
    len: usize,
    primes: Vec<u64>,
    residues: Vec<Vec<u64>>,
    /// A lower bound on log2 of the modulus.
    log2: f64,
}

impl Crt {
    fn new(len: usize) -> Self {
        Crt {
            len,
            primes: Vec::new(),
            residues: Vec::new(),
            log2: 0.0,
        }
    }
    fn add(&mut self, residues: &[u64], p: u64) {
        debug_assert_eq!(residues.len(), self.len);
        self.primes.push(p);
        self.residues.push(residues.to_vec());
        self.log2 += log2_prime(p);
    }
    /// A lower bound on the bit length of the modulus.
    fn bits(&self) -> u64 {
        self.log2.max(0.0) as u64
    }
    /// The values in the symmetric range `(−M/2, M/2]`, `M` the product of the primes.
    fn signed(&self) -> Vec<BigInt> {
        let k = self.primes.len();
        if k == 0 {
            return vec![BigInt::zero(); self.len];
        }
        // w[j][i] = p_0 ⋯ p_(i−1) mod p_j, and the inverse of p_0 ⋯ p_(j−1) mod p_j
        let mut w: Vec<Vec<u64>> = Vec::with_capacity(k);
        let mut inv: Vec<u64> = Vec::with_capacity(k);
        for (j, &pj) in self.primes.iter().enumerate() {
            let mut row = Vec::with_capacity(j);
            let mut prod = 1u64;
            for &pi in &self.primes[..j] {
                row.push(prod);
                prod = prod * (pi % pj) % pj;
            }
            inv.push(inv_mod(prod, pj).unwrap_or(0));
            w.push(row);
        }
        let mut modulus = BigInt::one();
        for &p in &self.primes {
            modulus *= p;
        }
        let half = &modulus >> 1;
        let mut digits = vec![0u64; k];
        (0..self.len)
            .map(|v| {
                for j in 0..k {
                    let pj = self.primes[j];
                    let prefix = dot(&digits[..j], &w[j], pj);
                    let r = self.residues[j][v];
                    digits[j] = (r + pj - prefix) % pj * inv[j] % pj;
                }
                let mut value = BigInt::zero();
                for j in (0..k).rev() {
                    value = value * self.primes[j] + digits[j];
                }
                if value > half {
                    value - &modulus
                } else {
                    value
                }
            })
            .collect()
    }
}

/// An upper bound on `log2 ‖row‖` (0 for a zero row): the Euclidean norm itself for word-size
/// entries (with a margin for rounding), else `max bits + ½ log2 len` — the row factor of every
/// Hadamard bound here.
fn row_log2_norm(row: &[BigInt]) -> f64 {
    log2_norm(row.iter())
}

/// [`row_log2_norm`] of any line of entries (a column too).
fn log2_norm<'a>(entries: impl Iterator<Item = &'a BigInt> + Clone) -> f64 {
    let small: Option<Vec<i64>> = entries.clone().map(ToPrimitive::to_i64).collect();
    if let Some(v) = small.filter(|v| v.iter().all(|x| x.unsigned_abs() < 1 << 26)) {
        let sq: f64 = v.iter().map(|&x| (x as f64) * (x as f64)).sum();
        return if sq == 0.0 {
            0.0
        } else {
            0.5 * sq.log2() + 1e-9
        };
    }
    let len = entries.clone().count();
    let max_bits = entries.map(BigInt::bits).max().unwrap_or(0) as f64;
    if max_bits == 0.0 {
        0.0
    } else {
        max_bits + 0.5 * (len as f64).log2()
    }
}

/// Bits of a bound on the coefficients of the characteristic polynomial of an integer matrix:
/// `|c_k| ≤ C(n, k) · Π (k largest row norms)` (Hadamard on each k × k principal minor), or
/// the same with column norms (a minor is its transpose's) when that is smaller — a gain in
/// one column (A + LC with C = e₁ᵀ) puts a large entry in every row but in one column only.
fn charpoly_bound_bits(a: &Matrix<BigInt>) -> u64 {
    let n = a.rows();
    let rows: Vec<f64> = (0..n).map(|i| row_log2_norm(a.row(i))).collect();
    let columns: Vec<f64> = (0..n)
        .map(|j| log2_norm((0..n).map(|i| a.get(i, j))))
        .collect();
    let bound = |mut norms: Vec<f64>| {
        norms.sort_by(|x, y| y.total_cmp(x));
        let mut best = 0f64;
        let mut acc = 0f64;
        let mut log_binom = 0f64;
        for k in 1..=n {
            acc += norms[k - 1].max(0.0);
            log_binom += ((n - k + 1) as f64 / k as f64).log2();
            best = best.max(acc + log_binom);
        }
        best
    };
    bound(rows).min(bound(columns)).ceil() as u64 + 2
}

/// The characteristic polynomial of an integer matrix (ascending coefficients), exact.
pub fn charpoly_integer(a: &Matrix<BigInt>) -> Vec<BigInt> {
    let n = a.rows();
    let need = charpoly_bound_bits(a) + 1;
    // the primes whose product passes the bound, known in advance
    let mut chosen = Vec::new();
    let mut bits = 0f64;
    for p in primes() {
        if bits > need as f64 {
            break;
        }
        chosen.push(p);
        bits += log2_prime(p);
    }
    let image = |p: u64| {
        let h: Vec<Vec<u64>> = (0..n)
            .map(|i| a.row(i).iter().map(|x| int_mod(x, p)).collect())
            .collect();
        charpoly_mod(h, p)
    };
    let images = map_primes(&chosen, n * n * n, image);
    let mut crt = Crt::new(n + 1);
    for (p, r) in chosen.iter().zip(&images) {
        crt.add(r, *p);
    }
    crt.signed()
}

/// A lower bound on `log2 p` (rounding of the logarithm taken off).
fn log2_prime(p: u64) -> f64 {
    (p as f64).log2() - 1e-9
}

/// Below this many word operations in all (primes × the work of one image) the images are
/// computed on one thread: starting a second thread, and asking the system how many cores
/// there are (it reads the cgroup's files), costs about 0.1 ms of CPU, as much as all the
/// images of a 10-state design — and a second thread never lowers the CPU time, only the
/// wall-clock time of long runs.
const THREADED_WORK: usize = 1 << 20;

/// `f(p)` for every prime, on two threads where the platform has them and the work (`work`
/// word operations per prime, roughly) is worth a second thread (the images are independent;
/// the order of the results is the order of the primes).
fn map_primes<T: Send>(primes: &[u64], work: usize, f: impl Fn(u64) -> T + Sync) -> Vec<T> {
    let worth_a_thread = primes.len() >= 4 && primes.len().saturating_mul(work) >= THREADED_WORK;
    #[cfg(target_arch = "wasm32")]
    let _ = worth_a_thread; // one thread in the browser
    #[cfg(not(target_arch = "wasm32"))]
    if worth_a_thread {
        let threads = std::thread::available_parallelism().map_or(1, |t| t.get().min(2));
        if threads > 1 {
            let (first, second) = primes.split_at(primes.len() / 2);
            let f = &f;
            return std::thread::scope(|scope| {
                let other = scope.spawn(move || second.iter().map(|&p| f(p)).collect::<Vec<T>>());
                let mut out: Vec<T> = first.iter().map(|&p| f(p)).collect();
                match other.join() {
                    Ok(rest) => out.extend(rest),
                    Err(_) => out.extend(second.iter().map(|&p| f(p))),
                }
                out
            });
        }
    }
    primes.iter().map(|&p| f(p)).collect()
}

/// An integer matrix scaled from a rational one, with entries mod p fast when they fit `i64`.
pub(crate) struct IntMatrix {
    rows: usize,
    cols: usize,
    words: Words,
    big: Vec<BigInt>,
}

/// How an integer matrix is reduced modulo each prime: every entry a machine word, or every
/// entry's sign and 32-bit digits (most significant first), taken from num-bigint once rather
/// than once per prime.
enum Words {
    Small(Vec<i64>),
    Digits(Vec<(bool, Vec<u32>)>),
}

impl IntMatrix {
    pub(crate) fn new(rows: usize, cols: usize, big: Vec<BigInt>) -> Self {
        let words = match big.iter().map(ToPrimitive::to_i64).collect() {
            Some(small) => Words::Small(small),
            None => Words::Digits(
                big.iter()
                    .map(|x| {
                        let digits = x.magnitude().iter_u32_digits().rev().collect();
                        (x.sign() == num_bigint::Sign::Minus, digits)
                    })
                    .collect(),
            ),
        };
        IntMatrix {
            rows,
            cols,
            words,
            big,
        }
    }
    /// Row-major residues.
    pub(crate) fn residues(&self, p: u64) -> Vec<u64> {
        match &self.words {
            Words::Small(v) => v.iter().map(|&x| x.rem_euclid(p as i64) as u64).collect(),
            Words::Digits(v) => {
                let br = Barrett::new(p);
                v.iter()
                    .map(|(negative, d)| residue(*negative, d.iter().copied(), br))
                    .collect()
            }
        }
    }
    /// log2 of the Frobenius norm (an upper bound).
    pub(crate) fn log2_norm(&self) -> f64 {
        let max_bits = self.big.iter().map(|x| x.bits()).max().unwrap_or(0) as f64;
        max_bits + 0.5 * ((self.rows * self.cols) as f64).log2()
    }
}

/// `a`'s rows scaled to integers (row i times the lcm of its denominators), and the product of
/// the scales.
fn scaled_rows(a: &Matrix<Rational>) -> (IntMatrix, BigInt) {
    let mut big = Vec::with_capacity(a.rows() * a.cols());
    let mut scale = BigInt::one();
    for i in 0..a.rows() {
        let d = Rational::common_denominator(a.row(i));
        big.extend(a.row(i).iter().map(|x| x.scale_to_integer(&d)));
        scale *= d;
    }
    (IntMatrix::new(a.rows(), a.cols(), big), scale)
}

/// `a` times one common denominator of all its entries: an integer matrix with the same
/// eigenvectors, Krylov spaces and row spaces (its eigenvalues scaled by that denominator).
fn scaled_whole(a: &Matrix<Rational>) -> IntMatrix {
    let d = Rational::common_denominator(a.entries());
    IntMatrix::new(
        a.rows(),
        a.cols(),
        a.entries().iter().map(|x| x.scale_to_integer(&d)).collect(),
    )
}

/// Swaps rows `a` and `b` of the row-major `n`-column matrix `m` and of the `k`-column
/// right-hand sides `rhs` (a pivot brought up).
fn swap_rows(m: &mut [u64], rhs: &mut [u64], n: usize, k: usize, a: usize, b: usize) {
    for j in 0..n {
        m.swap(a * n + j, b * n + j);
    }
    for j in 0..k {
        rhs.swap(a * k + j, b * k + j);
    }
}

/// `u64` dot product mod p with one reduction per 4 terms (products of residues < 2⁶²).
#[inline]
pub(crate) fn dot(x: &[u64], y: &[u64], p: u64) -> u64 {
    let mut acc: u128 = 0;
    for (a, b) in x.iter().zip(y) {
        acc += (*a * *b) as u128;
    }
    (acc % p as u128) as u64
}

/// LU-style elimination mod p of the n×n matrix `m` (row-major) with right-hand sides `rhs`
/// (n×k, row-major): returns `(det mod p, solution mod p)`, or `None` when singular mod p.
pub(crate) fn det_and_solve_mod(
    mut m: Vec<u64>,
    n: usize,
    mut rhs: Vec<u64>,
    k: usize,
    p: u64,
) -> Option<(u64, Vec<u64>)> {
    let br = Barrett::new(p);
    let mut det = 1u64;
    // Delayed reduction: an entry below and right of the pivots takes one product (at most
    // (p − 1)²) per step without being reduced; starting from a value below p it holds
    // `limit` of them within 64 bits (4 for p near 2³¹, where a fixed 3 was used before; 16
    // below 2³⁰), so the trailing block is reduced every `limit`-th step (Barrett's reduction
    // is exact for any 64-bit input), the pivot column and row as they are used.
    let square = (p - 1).saturating_mul(p - 1).max(1);
    let most = u32::try_from((u64::MAX - (p - 1)) / square).unwrap_or(u32::MAX);
    let limit = most.clamp(1, 64);
    let mut pending = 0u32;
    for col in 0..n {
        if pending > 0 {
            for i in col..n {
                m[i * n + col] = br.reduce(m[i * n + col]);
            }
        }
        let piv = (col..n).find(|&i| m[i * n + col] != 0)?;
        if piv != col {
            swap_rows(&mut m, &mut rhs, n, k, piv, col);
            det = (p - det) % p;
        }
        if pending > 0 {
            for j in col + 1..n {
                m[col * n + j] = br.reduce(m[col * n + j]);
            }
            for j in 0..k {
                rhs[col * k + j] = br.reduce(rhs[col * k + j]);
            }
        }
        let pv = m[col * n + col];
        det = br.mul(det, pv);
        let inv = inv_mod(pv, p)?;
        for j in col..n {
            m[col * n + j] = br.mul(m[col * n + j], inv);
        }
        for j in 0..k {
            rhs[col * k + j] = br.mul(rhs[col * k + j], inv);
        }
        for i in col + 1..n {
            let u = m[i * n + col];
            if u == 0 {
                continue;
            }
            let neg_u = p - u;
            let (top, below) = m.split_at_mut(i * n);
            let pivot_row = &top[col * n + col + 1..col * n + n];
            // both factors are below p < 2^31: as 32-bit words the product is one
            // 32 × 32 → 64-bit multiply, which the compiler vectorises (two to four lanes)
            let factor = neg_u as u32;
            for (x, &y) in below[col + 1..n].iter_mut().zip(pivot_row) {
                *x += u64::from(factor) * u64::from(y as u32);
            }
            // the pivot column's entry is eliminated: exactly zero
            below[col] = 0;
            let (top, below) = rhs.split_at_mut(i * k);
            for (x, &y) in below[..k].iter_mut().zip(&top[col * k..col * k + k]) {
                *x += neg_u * y;
            }
        }
        pending += 1;
        if pending == limit {
            for i in col + 1..n {
                for j in col + 1..n {
                    m[i * n + j] = br.reduce(m[i * n + j]);
                }
                for j in 0..k {
                    rhs[i * k + j] = br.reduce(rhs[i * k + j]);
                }
            }
            pending = 0;
        }
    }
    // back substitution (unit upper triangular)
    for col in (0..n).rev() {
        for i in 0..col {
            let u = m[i * n + col];
            if u == 0 {
                continue;
            }
            let neg_u = p - u;
            for j in 0..k {
                rhs[i * k + j] = br.reduce(rhs[i * k + j] + neg_u * rhs[col * k + j]);
            }
        }
    }
    Some((det, rhs))
}

/// Chinese remaindering of `det` and `det · x` up to `bits`, then `x = (det·x)/det`.
/// `residues(p)` gives `(det mod p, x mod p)` or `None` for a prime dividing `det`.
pub(crate) fn lift_cramer(
    len: usize,
    bits: u64,
    mut residues: impl FnMut(u64) -> Option<(u64, Vec<u64>)>,
) -> Option<(BigInt, Vec<BigInt>)> {
    let mut crt = Crt::new(len + 1);
    let mut unlucky = 0;
    for p in elimination_primes() {
        if crt.bits() > bits {
            let v = crt.signed();
            return Some((v[len].clone(), v[..len].to_vec()));
        }
        match residues(p) {
            Some((d, x)) if d != 0 => {
                let mut r: Vec<u64> = x.iter().map(|xi| xi * d % p).collect();
                r.push(d);
                crt.add(&r, p);
            }
            _ => {
                unlucky += 1;
                if unlucky > 40 {
                    return None;
                }
            }
        }
    }
    None
}

/// Rank of a row-major `rows × cols` matrix mod p, by elimination.
fn rank_mod(mut m: Vec<u64>, rows: usize, cols: usize, p: u64) -> usize {
    let br = Barrett::new(p);
    let mut rank = 0;
    for col in 0..cols {
        if rank == rows {
            break;
        }
        let Some(piv) = (rank..rows).find(|&i| m[i * cols + col] != 0) else {
            continue;
        };
        for j in 0..cols {
            m.swap(piv * cols + j, rank * cols + j);
        }
        let inv = inv_mod(m[rank * cols + col], p).unwrap_or(0);
        for i in rank + 1..rows {
            let u = br.mul(m[i * cols + col], inv);
            if u == 0 {
                continue;
            }
            let neg_u = p - u;
            for j in col..cols {
                m[i * cols + j] = br.reduce(m[i * cols + j] + neg_u * m[rank * cols + j]);
            }
        }
        rank += 1;
    }
    rank
}

/// Whether `a` has full rank, `min(rows, cols)`, proved by its rank modulo one prime (a rank
/// mod p is never larger than the rank over Q). `false` means "not proved": the caller decides
/// exactly (a rank deficiency cannot be proved modulo a prime).
pub fn has_full_rank(a: &Matrix<Rational>) -> bool {
    let (rows, cols) = (a.rows(), a.cols());
    let full = rows.min(cols);
    let (scaled, _) = scaled_rows(a);
    primes()
        .take(3)
        .any(|p| rank_mod(scaled.residues(p), rows, cols, p) == full)
}

/// Whether the pair (A, C) is proved observable modulo a prime: the rows C, CA, CA², … are
/// reduced against an echelon basis as they are formed, and the proof is complete once the
/// basis has n rows — for p outputs that is often after ⌈n/p⌉ blocks, never the whole pn × n
/// matrix O_n. Scaling A and the rows of C to integers changes no row space, and a rank mod p
/// is never larger than the rank over Q, so `true` is a proof; `false` means "not proved" (the
/// caller decides exactly). O(n³) word operations per prime, at most three primes.
pub fn observable_mod_prime(a: &Matrix<Rational>, c: &Matrix<Rational>) -> bool {
    let n = a.rows();
    if n == 0 || a.cols() != n || c.cols() != n {
        return false;
    }
    let scaled_a = scaled_whole(a);
    let (scaled_c, _) = scaled_rows(c);
    primes().take(3).any(|p| {
        let br = Barrett::new(p);
        let am = scaled_a.residues(p);
        let mut block: Vec<Vec<u64>> = scaled_c
            .residues(p)
            .chunks(n)
            .map(<[u64]>::to_vec)
            .collect();
        // echelon rows, each with its pivot column and a leading 1
        let mut basis: Vec<(usize, Vec<u64>)> = Vec::with_capacity(n);
        for _ in 0..n {
            let before = basis.len();
            for row in &block {
                let mut r = row.clone();
                for (col, b) in &basis {
                    let u = r[*col];
                    if u != 0 {
                        let neg_u = p - u;
                        for (x, y) in r.iter_mut().zip(b) {
                            *x = br.reduce(*x + neg_u * y);
                        }
                    }
                }
                if let Some(col) = r.iter().position(|&x| x != 0) {
                    let inv = inv_mod(r[col], p).unwrap_or(0);
                    for x in r.iter_mut() {
                        *x = br.mul(*x, inv);
                    }
                    basis.push((col, r));
                    if basis.len() == n {
                        return true;
                    }
                }
            }
            if basis.len() == before {
                // the rows' span is A-invariant modulo p: no later block adds a row
                return false;
            }
            // the next block, row · A
            block = block
                .iter()
                .map(|row| {
                    let mut next = vec![0u64; n];
                    for (k, &x) in row.iter().enumerate() {
                        if x != 0 {
                            let a_row = &am[k * n..(k + 1) * n];
                            for (y, &z) in next.iter_mut().zip(a_row) {
                                *y = br.reduce(*y + x * z);
                            }
                        }
                    }
                    next
                })
                .collect();
        }
        false
    })
}

/// Whether the square matrix `a` is proved not nilpotent, by its characteristic polynomial
/// modulo one prime: a nilpotent `a` has `det(zI − a) = zⁿ`, and so has `d·a` (d a common
/// denominator, an integer matrix) modulo every prime. A nonzero trace decides it in O(n);
/// otherwise one Hessenberg reduction, O(n³) word operations. `false` means "not refuted" (the
/// caller decides exactly).
pub fn surely_not_nilpotent(a: &Matrix<Rational>) -> bool {
    let n = a.rows();
    if n == 0 || a.cols() != n {
        return false;
    }
    if !(0..n)
        .map(|i| a.get(i, i))
        .fold(Rational::zero(), |s, x| s + x)
        .is_zero()
    {
        return true;
    }
    let scaled = scaled_whole(a);
    let Some(p) = primes().next() else {
        return false;
    };
    let m = scaled.residues(p);
    let h: Vec<Vec<u64>> = m.chunks(n).map(<[u64]>::to_vec).collect();
    charpoly_mod(h, p)[..n].iter().any(|&c| c != 0)
}

/// Whether the trace of a square matrix, given by its diagonal's fractions `n/d` (`d > 0`,
/// not necessarily in lowest terms), is proved nonzero — so the matrix is not nilpotent, as
/// [`surely_not_nilpotent`]'s first test decides on exact entries: the sum as one fraction
/// `N/D` modulo a prime dividing none of the denominators, where `N ≢ 0` proves `N ≠ 0`.
/// `false` means "not proved": a zero trace, or each of three primes dividing a denominator or
/// missing a nonzero `N`. Cost: two word products a diagonal entry.
pub(crate) fn trace_is_nonzero(diagonal: impl Iterator<Item = (i64, i64)> + Clone) -> bool {
    primes().take(3).any(|p| {
        let residue = |x: i64| x.rem_euclid(p as i64) as u64;
        if diagonal.clone().any(|(_, d)| residue(d) == 0) {
            return false;
        }
        // N/D + n/d = (N·d + n·D)/(D·d), every product below 2⁶² (p < 2³¹)
        let (sum, _) = diagonal.clone().fold((0u64, 1u64), |(num, den), (n, d)| {
            let (n, d) = (residue(n), residue(d));
            ((num * d % p + n * den % p) % p, den * d % p)
        });
        sum != 0
    })
}

/// Whether the square matrix `a` is cyclic (non-derogatory): some vector v makes the Krylov
/// matrix [v, Av, …, Aⁿ⁻¹v] nonsingular, so the minimal polynomial of `a` is its
/// characteristic polynomial. Proved modulo a prime — a Krylov matrix of full rank mod p has
/// full rank over Q (for `dA`, d a common denominator, which has the same Krylov spaces) —
/// with a few pseudo-random vectors, O(n³) word operations each. `false` means "not proved".
pub fn is_cyclic(a: &Matrix<Rational>) -> bool {
    let n = a.rows();
    if n == 0 || a.cols() != n {
        return false;
    }
    let scaled = scaled_whole(a);
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    primes().take(3).any(|p| {
        let m = scaled.residues(p);
        let mut krylov = Vec::with_capacity(n * n);
        let mut v: Vec<u64> = (0..n)
            .map(|_| {
                seed = seed
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (seed >> 33) % p
            })
            .collect();
        for _ in 0..n {
            krylov.extend_from_slice(&v);
            v = (0..n).map(|i| dot(&m[i * n..(i + 1) * n], &v, p)).collect();
        }
        rank_mod(krylov, n, n, p) == n
    })
}

/// The determinant of a square rational matrix, exact: the rows are scaled to integers, the
/// integer determinant is lifted by Chinese remaindering up to Hadamard's bound (exact by
/// construction), and the row scales are divided out once.
pub fn determinant_rational(a: &Matrix<Rational>) -> Rational {
    let n = a.rows();
    if n == 0 || a.cols() != n {
        return Rational::one();
    }
    let (ints, scale) = scaled_rows(a);
    let bits: f64 = (0..n)
        .map(|i| row_log2_norm(&ints.big[i * n..(i + 1) * n]).max(0.0))
        .sum();
    let mut crt = Crt::new(1);
    for p in elimination_primes() {
        if crt.bits() > bits.ceil() as u64 + 2 {
            break;
        }
        let det = det_and_solve_mod(ints.residues(p), n, Vec::new(), 0, p).map_or(0, |(d, _)| d);
        crt.add(&[det], p);
    }
    crate::algebra::fraction(crt.signed().swap_remove(0), scale)
}

/// Solves `A X = B` over the rationals exactly: `det(A)·X = adj(A)·B` is lifted by Chinese
/// remaindering up to a Hadamard bound, so the result is exact by construction. `None` when A is
/// singular (the caller reports it).
pub fn solve_rational(a: &Matrix<Rational>, b: &Matrix<Rational>) -> Option<Matrix<Rational>> {
    let (y, det) = solve_rational_scaled(a, b)?;
    let x: Vec<Rational> = y
        .into_iter()
        .map(|v| crate::algebra::fraction(v, det.clone()))
        .collect();
    Some(Matrix::from_fn(a.rows(), b.cols(), |i, j| {
        x[i * b.cols() + j].clone()
    }))
}

/// `A X = B` over the rationals as integers over one denominator, not reduced: `(Y, δ)` with
/// `X = Y/δ` (row-major), `δ` the determinant of `A` with its rows scaled to integers. A caller
/// that goes on computing with `X` (`P(A)·X` by Horner, which scales its input to one
/// denominator anyway) saves the reduction of every entry — a gcd of numbers as long as
/// `det A` each, a fifth of the solve's cost at order 40. `None` when A is singular.
pub(crate) fn solve_rational_scaled(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
) -> Option<(Vec<BigInt>, BigInt)> {
    let (n, k) = (a.rows(), b.cols());
    if n == 0 || a.cols() != n || b.rows() != n {
        return None;
    }
    // Scale each row of [A | B] to integers (the solution does not change).
    let (aug, _) = scaled_rows(&a.hstack(b).ok()?);
    let ai = IntMatrix::new(
        n,
        n,
        (0..n)
            .flat_map(|i| aug.big[i * (n + k)..i * (n + k) + n].to_vec())
            .collect(),
    );
    let bi = IntMatrix::new(
        n,
        k,
        (0..n)
            .flat_map(|i| aug.big[i * (n + k) + n..(i + 1) * (n + k)].to_vec())
            .collect(),
    );
    // |det A| ≤ Π ‖a_i‖; |adj(A) B| ≤ Π (n−1 largest ‖a_i‖) · √n · max |b|.
    let mut row_bits: Vec<f64> = (0..n)
        .map(|i| row_log2_norm(&ai.big[i * n..(i + 1) * n]))
        .collect();
    row_bits.sort_by(|x, y| y.total_cmp(x));
    let det_bits: f64 = row_bits.iter().sum();
    let b_bits =
        bi.big.iter().map(|x| x.bits()).max().unwrap_or(0) as f64 + 0.5 * (n as f64).log2();
    let num_bits = row_bits.iter().take(n.saturating_sub(1)).sum::<f64>() + b_bits;
    let bits = det_bits.max(num_bits).ceil() as u64 + 2;
    let (det, y) = lift_cramer(n * k, bits, |p| {
        det_and_solve_mod(ai.residues(p), n, bi.residues(p), k, p)
    })?;
    (!det.is_zero()).then_some((y, det))
}

#[cfg(test)]
mod tests {
    #[test]
    fn int_mod_agrees_with_bigint_remainder() {
        use num_bigint::BigInt;
        let values = [
            BigInt::from(0),
            BigInt::from(-1),
            BigInt::from(7) << 300u32,
            -(BigInt::from(123_456_789_i64) << 97u32) - 5,
            BigInt::from(u64::MAX) * BigInt::from(u64::MAX) + 17,
        ];
        for p in super::primes().take(3).chain([2, 3, 65_537]) {
            for x in &values {
                let expected = ((x % BigInt::from(p)) + BigInt::from(p)) % BigInt::from(p);
                assert_eq!(BigInt::from(super::int_mod(x, p)), expected, "{x} mod {p}");
            }
        }
    }

    use super::*;
    use crate::algebra::Ring;

    #[test]
    fn the_tables_are_the_generated_primes() {
        // the compiler's tables against a search from the bound down, and the first generated
        // prime after each table is the next prime below its last entry
        for (table, bound) in [
            (&PRIMES_BELOW_2_31, 1u64 << 31),
            (&PRIMES_BELOW_2_30, 1 << 30),
        ] {
            let searched: Vec<u64> = (1..bound / 2)
                .rev()
                .map(|k| 2 * k + 1)
                .filter(|&c| is_prime(c))
                .take(TABLED + 5)
                .collect();
            let taken: Vec<u64> = primes_after(table).take(TABLED + 5).collect();
            assert_eq!(taken, searched);
        }
        // and the first is the largest prime below 2³⁰, by trial division (not Miller–Rabin)
        let composite = |c: u64| {
            (2..)
                .take_while(|d| d * d <= c)
                .any(|d| c.is_multiple_of(d))
        };
        let first = elimination_primes().next().expect("a prime");
        assert!(first < 1 << 30 && !composite(first));
        assert!((first + 1..1 << 30).all(composite));
    }

    #[test]
    fn primes_are_prime_and_below_two_to_the_31() {
        let ps: Vec<u64> = primes().skip(4090).take(20).collect();
        assert_eq!(primes().next(), Some(2_147_483_647));
        // every odd number between two consecutive primes taken is composite: none skipped
        let first: Vec<u64> = primes().take(50).collect();
        for w in first.windows(2) {
            assert!((w[1] + 2..w[0]).step_by(2).all(|c| !is_prime(c)), "{w:?}");
        }
        assert_eq!(first[1], 2_147_483_629);
        assert_eq!(first[2], 2_147_483_587);
        assert!(ps.windows(2).all(|w| w[0] > w[1]));
        assert!(ps.iter().all(|&p| is_prime(p) && p < 1 << 31));
        assert!(!is_prime(2_147_483_649));
    }

    #[test]
    fn chinese_remaindering_recovers_signed_integers() {
        let x = BigInt::from(-355_113_000_000_000_i64) * BigInt::from(1_000_000_007_i64);
        let mut crt = Crt::new(1);
        for p in primes().take(4) {
            crt.add(&[int_mod(&x, p)], p);
        }
        assert_eq!(crt.signed()[0], x);
    }

    #[test]
    fn cramer_solve_matches_fraction_free_elimination() {
        let r = |v: i64| Rational::from_i64(v);
        let h = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let a = Matrix::from_rows(vec![
            vec![r(2), h(-3, 2), r(1)],
            vec![r(4), r(-5), h(1, 7)],
            vec![r(1), r(2), r(-1)],
        ])
        .unwrap();
        let b = Matrix::from_rows(vec![
            vec![r(1), r(0)],
            vec![h(2, 3), r(1)],
            vec![r(-5), r(0)],
        ])
        .unwrap();
        let x = solve_rational(&a, &b).unwrap();
        assert_eq!(a.mul(&x).unwrap(), b);
        let singular = Matrix::from_rows(vec![vec![r(1), r(2)], vec![r(2), r(4)]]).unwrap();
        assert!(solve_rational(&singular, &Matrix::identity(2)).is_none());
    }

    /// The delayed reduction against elimination reducing every operation, on matrices whose
    /// residues sit next to the largest prime (the largest products, so the overflow margin is
    /// tested), with several right-hand sides, singular ones included.
    #[test]
    fn delayed_reduction_matches_reducing_every_step() {
        fn reference(
            m: &[u64],
            n: usize,
            rhs: &[u64],
            k: usize,
            p: u64,
        ) -> Option<(u64, Vec<u64>)> {
            let (mut m, mut rhs) = (m.to_vec(), rhs.to_vec());
            let mul = |a: u64, b: u64| (a as u128 * b as u128 % p as u128) as u64;
            let mut det = 1u64;
            for col in 0..n {
                let piv = (col..n).find(|&i| m[i * n + col] != 0)?;
                if piv != col {
                    super::swap_rows(&mut m, &mut rhs, n, k, piv, col);
                    det = (p - det) % p;
                }
                det = mul(det, m[col * n + col]);
                let inv = super::inv_mod(m[col * n + col], p)?;
                for j in col..n {
                    m[col * n + j] = mul(m[col * n + j], inv);
                }
                for j in 0..k {
                    rhs[col * k + j] = mul(rhs[col * k + j], inv);
                }
                for i in 0..n {
                    let u = m[i * n + col];
                    if i == col || u == 0 {
                        continue;
                    }
                    for j in col..n {
                        m[i * n + j] = (m[i * n + j] + p - mul(u, m[col * n + j])) % p;
                    }
                    for j in 0..k {
                        rhs[i * k + j] = (rhs[i * k + j] + p - mul(u, rhs[col * k + j])) % p;
                    }
                }
            }
            Some((det, rhs))
        }
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        // entries near p − 1, the largest products: the delayed reductions at their limit (4
        // products near 2³¹, 16 below 2³⁰, 64 for small primes) on orders past it
        let primes = [
            super::primes().next().unwrap(),
            super::elimination_primes().next().unwrap(),
            65_537,
            3,
        ];
        for (p, n) in primes
            .into_iter()
            .flat_map(|p| (1..=14).chain([20, 33, 70]).map(move |n| (p, n)))
        {
            for trial in 0..if n > 14 { 4 } else { 20 } {
                let k = trial % 3;
                let mut m: Vec<u64> = (0..n * n).map(|_| p - 1 - next() % p.min(5)).collect();
                if trial % 7 == 6 && n > 1 {
                    // a repeated row: singular
                    for j in 0..n {
                        m[n + j] = m[j];
                    }
                }
                let rhs: Vec<u64> = (0..n * k).map(|_| next() % p).collect();
                let got = super::det_and_solve_mod(m.clone(), n, rhs.clone(), k, p);
                assert_eq!(
                    got,
                    reference(&m, n, &rhs, k, p),
                    "p = {p}, n = {n}, trial {trial}"
                );
            }
        }
    }

    #[test]
    fn modular_charpoly_matches_berkowitz() {
        let r = |v: i64| Rational::from_i64(v);
        let a = Matrix::from_rows(vec![
            vec![r(2), r(-3), r(1)],
            vec![r(4), r(-5), r(0)],
            vec![r(1), r(2), r(-1)],
        ])
        .unwrap();
        let exact = crate::linalg::berkowitz(&a, "s").unwrap();
        let ints = a.map(|x| x.numer().clone());
        let expected: Vec<BigInt> = exact.coeffs().iter().map(|c| c.numer().clone()).collect();
        assert_eq!(charpoly_integer(&ints), expected);
    }

    /// A matrix with large numbers in one column (A + LC, C = e₁ᵀ) or one row: the bound by
    /// the smaller of the row and column norms still covers the coefficients, which come out
    /// as Berkowitz's; and the column bound is the smaller one for the column.
    #[test]
    fn a_large_column_or_row_takes_the_smaller_bound() {
        let big = BigInt::from(3).pow(120);
        for column in [true, false] {
            let n = 9;
            let a = Matrix::from_fn(n, n, |i, j| {
                let small = BigInt::from((i as i64 * 7 + j as i64 * 3) % 9 - 4);
                if (column && j == 0) || (!column && i == 0) {
                    &big * BigInt::from(i as i64 + j as i64 + 1) - small
                } else {
                    small
                }
            });
            let as_rational = a.map(|x| Rational::from_integer(x.clone()));
            let exact = crate::linalg::berkowitz(&as_rational, "s").unwrap();
            let expected: Vec<BigInt> = exact.coeffs().iter().map(|c| c.numer().clone()).collect();
            assert_eq!(charpoly_integer(&a), expected, "column {column}");
            // every row holds a large entry, one column does (or the other way round): the
            // bound is about one large entry's bits, not n of them
            assert!(charpoly_bound_bits(&a) < 3 * big.bits(), "column {column}");
        }
    }
}
