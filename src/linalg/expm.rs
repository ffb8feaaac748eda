//! The matrix exponential e^X in `f64`, for the zero-order hold.
//!
//! **Algorithm.** Scaling and squaring with a diagonal Padé approximant r_m = p_m/q_m of degree
//! m ∈ {3, 5, 7, 9, 13}, chosen as Al-Mohy and Higham choose it ("A new scaling and squaring
//! algorithm for the matrix exponential", SIAM J. Matrix Anal. Appl. 31, 2009; SciPy's `expm`
//! follows it): the smallest m whose bound on the backward error, taken from the norms
//! d_k = ‖X^k‖₁^(1/k) of the even powers, is below the unit roundoff. Past degree 9 the matrix
//! is scaled by 2^−s and the approximant squared s times. The norms are the formed powers' own
//! (each power is needed anyway, but X⁸ where a bound decides without it); the correction
//! ℓ(X, m), which raises s when |X|'s powers grow faster than X's, takes ‖ |X|^(2m+1) ‖₁ from
//! 2m + 1 products of |X|ᵀ with a vector. The approximant is the solution of q_m(X) R = p_m(X),
//! by LU factorisation with partial pivoting.
//!
//! **Identity.** The result is nalgebra's `exp` bit for bit — the same products (the bits of
//! nalgebra's `gemm`, made by [`super::gemm`]), the same order of every sum, the same pivots —
//! which a property test checks on random matrices across the five degrees and scalings. What changes is the working: each
//! matrix is made once into a buffer (nalgebra's operators make a new one per term), the
//! elimination runs over contiguous columns, the two triangular solves in tiles of 4 rows × 8
//! right-hand sides held in registers while the rows they are taken from stream past (each
//! entry still takes its terms one at a time, in the elimination's order: a second property
//! test compares the solve with nalgebra's LU solve up to order 60), and the ℓ correction's
//! vector products are column updates, which the compiler vectorises.
//!
//! **Cost.** At order N: the even powers, up to five products (X², X⁴, X⁶, and X⁸ or X¹⁰ when
//! degree 13's scaling needs them; X⁸ only for its norm when degree 7 is chosen, and not even
//! for that where a bound from ‖X⁶‖ and ‖X²‖ decides, `d8_below`), two more products for the
//! approximant, the factorisation (⅔N³ flops), the two triangular solves with N right-hand
//! sides (2N³) and s squarings. The products are [`super::gemm`]'s register tiles.
//! The factorisation, the solves and ℓ's vector products are compiled twice, for the
//! compiler's baseline x86-64 (two f64 a vector) and for AVX (four), and the second is chosen
//! where the processor has it; neither forms a fused multiply-add, which would change the bits.
//! In the baseline the solves were a third of the work at N = 101. Measured in session 27 (the
//! zero-order hold's augmented matrix of a random plant, 2-core machine, AVX): 0.0041 / 0.095 /
//! 0.630 ms at N = 11 / 51 / 101, against 0.0042 / 0.111 / 0.736 ms in the baseline, where
//! nalgebra's `exp` took 0.0051 / 0.131 / 0.756 ms and SciPy's `expm` on the benchmark's plants
//! 0.02 / 0.09 / 0.50 ms. Since then the tiles took the whole solve (factorisation included)
//! from 0.254 to 0.214 ms at N = 101 in a warm loop (row by row, every row taken was a pass
//! over all the right-hand sides, from the second-level cache), and degree 7 saves X⁸.

use nalgebra::DMatrix;

/// e^X, or `None` when the Padé denominator q_m(X) is singular to working precision (a
/// non-finite X, or one far outside the approximant's range).
pub fn expm(x: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    expm_choosing(x).map(|(e, _, _)| e)
}

/// e^X with the powers X² = X·X and X⁴ = X²·X² formed on the way, for a caller that needs them
/// too (the zero-order hold's error estimate): each as nalgebra's `gemm` makes it, so the same
/// bits as `&x * &x` and `&x2 * &x2`. Every X of order 2 or more has them (the choice of degree
/// starts from ‖X⁴‖ and ‖X⁶‖).
#[derive(Debug, Clone)]
pub struct Exponential {
    /// e^X.
    pub value: DMatrix<f64>,
    /// X², when it was formed.
    pub square: Option<DMatrix<f64>>,
    /// X⁴, when it was formed.
    pub fourth: Option<DMatrix<f64>>,
}

/// [`expm`], keeping X² and X⁴ ([`Exponential`]); `None` as for [`expm`].
pub fn expm_with_powers(x: &DMatrix<f64>) -> Option<Exponential> {
    let (value, _, powers) = expm_choosing(x)?;
    let [square, fourth, ..] = powers.map(|p| p.even).unwrap_or_default();
    Some(Exponential {
        value,
        square,
        fourth,
    })
}

/// The most squarings taken: a finite X needs at most about 1 030 (‖X‖₁ ≤ 2^1024·N) and ℓ a few
/// dozen more; beyond that its powers' norms overflowed, and [`expm`] refuses X rather than
/// square without end. The zero-order hold's Taylor check stops at the same count.
pub const MAX_SQUARINGS: u64 = 1_100;

/// The approximant chosen: its degree m and the number s of squarings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Choice {
    degree: usize,
    squarings: u64,
}

/// [`expm`], with the approximant it chose and the powers it formed (none at order 1).
fn expm_choosing(x: &DMatrix<f64>) -> Option<(DMatrix<f64>, Choice, Option<Powers<'_>>)> {
    let size = x.nrows();
    if size != x.ncols() {
        return None;
    }
    let unscaled = |degree| Choice {
        degree,
        squarings: 0,
    };
    if size == 1 {
        return Some((x.map(f64::exp), unscaled(0), None));
    }
    let mut powers = Powers::new(x);
    let eta_1 = powers.d(Even::Four).max(powers.d(Even::Six));
    if eta_1 < 1.495_585_217_958_292e-2 && ell(powers.a, 3) == 0 {
        let e = powers.pade(Low::Three)?;
        return Some((e, unscaled(3), Some(powers)));
    }
    let eta_2 = powers.d(Even::Four).max(powers.d(Even::Six));
    if eta_2 < 2.539_398_330_063_23e-1 && ell(powers.a, 5) == 0 {
        let e = powers.pade(Low::Five)?;
        return Some((e, unscaled(5), Some(powers)));
    }
    let eta_3_below = |powers: &mut Powers, theta: f64| {
        if d8_below(powers, THETA_7) {
            // then max(d6, d8) < θ ≥ θ7 exactly when d6 < θ, and X⁸ is not formed
            powers.d(Even::Six) < theta
        } else {
            powers.d(Even::Six).max(powers.d(Even::Eight)) < theta
        }
    };
    if eta_3_below(&mut powers, THETA_7) && ell(powers.a, 7) == 0 {
        let e = powers.pade(Low::Seven)?;
        return Some((e, unscaled(7), Some(powers)));
    }
    if eta_3_below(&mut powers, 2.097_847_961_257_068e0) && ell(powers.a, 9) == 0 {
        let e = powers.pade(Low::Nine)?;
        return Some((e, unscaled(9), Some(powers)));
    }
    let eta_3 = powers.d(Even::Six).max(powers.d(Even::Eight));
    let eta_4 = powers.d(Even::Eight).max(powers.d(Even::Ten));
    let eta_5 = eta_3.min(eta_4);
    let theta_13 = 4.25;
    let mut s = if eta_5 == 0.0 {
        0
    } else {
        let l2 = (eta_5 / theta_13).log2().ceil();
        if l2 < 0.0 {
            0
        } else {
            l2 as u64
        }
    };
    s = s.saturating_add(ell(&scaled(powers.a, 2.0_f64.powf(-(s as f64))), 13));
    if s > MAX_SQUARINGS {
        // ‖X⁸‖ or ‖X¹⁰‖ beyond f64 (so ‖X‖ beyond about 2^100): e^X overflows, or — a
        // rotation that fast — would come out of so many squarings with no digit right
        return None;
    }
    let mut r = powers.pade13_scaled(s)?;
    let mut square = DMatrix::<f64>::zeros(size, size);
    for _ in 0..s {
        super::gemm::product_into(&mut square, &r, &r);
        std::mem::swap(&mut r, &mut square);
    }
    Some((
        r,
        Choice {
            degree: 13,
            squarings: s,
        },
        Some(powers),
    ))
}

/// θ7: degree 7's bound on η3 = max(d6, d8) (Al-Mohy and Higham's table; nalgebra's value).
const THETA_7: f64 = 9.504_178_996_162_932e-1;

/// Whether d8 = ‖X⁸‖₁^(1/8), as [`Powers::d`] would compute it from the product X⁶·X², is
/// certainly below `theta`, without forming that product: the computed product C of the
/// computed X⁶ and X² has |C| ≤ (1 + γ_N)|X⁶||X²| entry by entry (γ_N = N·u/(1 − N·u)), so
/// ‖C‖₁ ≤ (1 + γ_N)‖X⁶‖₁‖X²‖₁, and with the rounding of the norms and the roots d8 is at most
/// (‖X⁶‖₁‖X²‖₁)^(1/8) times 1 + O(N·u) — which the margin of 10⁻⁶ covers up to orders of 10⁹.
/// Degree 7 does not use X⁸: a plant whose choice is decided without it saves a matrix product
/// (at order 101, a tenth of the zero-order hold's products). `false` (the product formed)
/// where d6 or the bound is not finite: `max` passes over a NaN, which the comparison on d6
/// alone would not.
fn d8_below(powers: &mut Powers, theta: f64) -> bool {
    let d6 = powers.d(Even::Six);
    let norms = powers.norm(Even::Six) * powers.norm(Even::Two);
    let bound = norms.powf(Even::Eight.root());
    d6.is_finite() && bound.is_finite() && bound * (1.0 + 1e-6) < theta
}

/// The even powers of X that the degrees use: X² … X¹⁰.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Even {
    Two,
    Four,
    Six,
    Eight,
    Ten,
}

impl Even {
    /// Where X^k is kept: k/2 − 1.
    fn slot(self) -> usize {
        match self {
            Even::Two => 0,
            Even::Four => 1,
            Even::Six => 2,
            Even::Eight => 3,
            Even::Ten => 4,
        }
    }
    /// The two factors X^k is the product of, in nalgebra's order (`None` is X itself): X² =
    /// X·X, X⁴ = X²·X², X⁶ = X⁴·X², X⁸ = X⁶·X², X¹⁰ = X⁶·X⁴.
    fn factors(self) -> (Option<Even>, Option<Even>) {
        match self {
            Even::Two => (None, None),
            Even::Four => (Some(Even::Two), Some(Even::Two)),
            Even::Six => (Some(Even::Four), Some(Even::Two)),
            Even::Eight => (Some(Even::Six), Some(Even::Two)),
            Even::Ten => (Some(Even::Six), Some(Even::Four)),
        }
    }
    /// 1/k, as nalgebra writes it, for d_k = ‖X^k‖₁^(1/k).
    fn root(self) -> f64 {
        match self {
            Even::Two => 0.5,
            Even::Four => 0.25,
            Even::Six => 1.0 / 6.0,
            Even::Eight => 1.0 / 8.0,
            Even::Ten => 1.0 / 10.0,
        }
    }
}

/// The degrees below 13, whose approximants are formed unscaled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Low {
    Three,
    Five,
    Seven,
    Nine,
}

impl Low {
    /// The coefficients b₀ … b_m of p_m (q_m has the same with alternating signs).
    fn coefficients(self) -> &'static [f64] {
        match self {
            Low::Three => &[120.0, 60.0, 12.0, 1.0],
            Low::Five => &[30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0],
            Low::Seven => &[
                17_297_280.0,
                8_648_640.0,
                1_995_840.0,
                277_200.0,
                25_200.0,
                1_512.0,
                56.0,
                1.0,
            ],
            Low::Nine => &[
                17_643_225_600.0,
                8_821_612_800.0,
                2_075_673_600.0,
                302_702_400.0,
                30_270_240.0,
                2_162_160.0,
                110_880.0,
                3_960.0,
                90.0,
                1.0,
            ],
        }
    }
    /// The even powers it needs, X² up to X^(m − 1).
    fn evens(self) -> &'static [Even] {
        match self {
            Low::Three => &[Even::Two],
            Low::Five => &[Even::Two, Even::Four],
            Low::Seven => &[Even::Two, Even::Four, Even::Six],
            Low::Nine => &[Even::Two, Even::Four, Even::Six, Even::Eight],
        }
    }
}

/// X and its even powers, each formed once, with their exact norms d_k = ‖X^k‖₁^(1/k).
struct Powers<'a> {
    a: &'a DMatrix<f64>,
    /// X², X⁴, X⁶, X⁸, X¹⁰ as they are needed.
    even: [Option<DMatrix<f64>>; 5],
    /// ‖X^k‖₁ for each, once computed (the choice of degree asks for most of them more than
    /// once: at order 101 eight passes over a matrix became three).
    norms: [Option<f64>; 5],
}

impl<'a> Powers<'a> {
    fn new(a: &'a DMatrix<f64>) -> Self {
        Self {
            a,
            even: [None, None, None, None, None],
            norms: [None; 5],
        }
    }

    /// X^k, formed from its two factors the first time it is asked for.
    fn power(&mut self, k: Even) -> &DMatrix<f64> {
        if self.even[k.slot()].is_none() {
            let (left, right) = k.factors();
            for factor in [left, right].into_iter().flatten() {
                self.power(factor);
            }
            let factor = |f: Option<Even>| match f {
                None => self.a,
                Some(e) => self.even[e.slot()]
                    .as_ref()
                    .unwrap_or_else(|| unreachable!("formed just above")),
            };
            let (l, r) = (factor(left), factor(right));
            self.even[k.slot()] = Some(super::gemm::product(l, r));
        }
        self.even[k.slot()]
            .as_ref()
            .unwrap_or_else(|| unreachable!("formed just above"))
    }

    /// ‖X^k‖₁.
    fn norm(&mut self, k: Even) -> f64 {
        if let Some(norm) = self.norms[k.slot()] {
            return norm;
        }
        let norm = one_norm(self.power(k));
        self.norms[k.slot()] = Some(norm);
        norm
    }

    /// d_k = ‖X^k‖₁^(1/k).
    fn d(&mut self, k: Even) -> f64 {
        self.norm(k).powf(k.root())
    }

    /// r_m(X) for m ∈ {3, 5, 7, 9}: U = X·Σ b_(2j+1) X^(2j), V = Σ b_(2j) X^(2j).
    fn pade(&mut self, degree: Low) -> Option<DMatrix<f64>> {
        let b = degree.coefficients();
        let top = degree.evens().len(); // the highest even power is X^(2·top)
        for &k in degree.evens() {
            self.power(k);
        }
        let even = |k: usize| {
            self.even[k - 1]
                .as_ref()
                .unwrap_or_else(|| unreachable!("formed above"))
        };
        // the sums from the highest power down, then the identity's term (nalgebra's order)
        let sum = |parity: usize| {
            let mut terms = (1..=top).rev().map(|k| (even(k), b[2 * k + parity]));
            let (first, c) = terms.next().unwrap_or_else(|| unreachable!("m ≥ 3"));
            let mut acc = scaled(first, c);
            for (term, c) in terms {
                add_scaled(&mut acc, term, c);
            }
            add_identity(&mut acc, b[parity]);
            acc
        };
        let u = super::gemm::product(self.a, &sum(1));
        let v = sum(0);
        // the powers above X⁴ are done with (X² and X⁴ go on to the caller): their room, and
        // the odd sum's, to the solve
        for power in &mut self.even[2..] {
            *power = None;
        }
        solve_p_q(u, v)
    }

    /// r_13(X/2^s), its powers the unscaled ones times 2^(−ks).
    fn pade13_scaled(&mut self, s: u64) -> Option<DMatrix<f64>> {
        let b: [f64; 14] = [
            64_764_752_532_480_000.0,
            32_382_376_266_240_000.0,
            7_771_770_303_897_600.0,
            1_187_353_796_428_800.0,
            129_060_195_264_000.0,
            10_559_470_521_600.0,
            670_442_572_800.0,
            33_522_128_640.0,
            1_323_241_920.0,
            40_840_800.0,
            960_960.0,
            16_380.0,
            182.0,
            1.0,
        ];
        let s = s as f64;
        let mb = scaled(self.a, 2.0_f64.powf(-s));
        let mb2 = scaled(self.power(Even::Two), 2.0_f64.powf(-2.0 * s));
        let mb4 = scaled(self.power(Even::Four), 2.0_f64.powf(-4.0 * s));
        let mb6 = scaled(self.power(Even::Six), 2.0_f64.powf(-6.0 * s));
        // X⁶·(b₁₃X⁶ + b₁₁X⁴ + b₉X²) + b₇X⁶ + b₅X⁴ + b₃X² + b₁I, and the even one alike
        let half = |high: [usize; 3], low: [usize; 4]| {
            let mut inner = scaled(&mb6, b[high[0]]);
            add_scaled(&mut inner, &mb4, b[high[1]]);
            add_scaled(&mut inner, &mb2, b[high[2]]);
            let mut acc = super::gemm::product(&mb6, &inner);
            add_scaled(&mut acc, &mb6, b[low[0]]);
            add_scaled(&mut acc, &mb4, b[low[1]]);
            add_scaled(&mut acc, &mb2, b[low[2]]);
            add_identity(&mut acc, b[low[3]]);
            acc
        };
        let inner = half([13, 11, 9], [7, 5, 3, 1]);
        let u = super::gemm::product(&mb, &inner);
        let v = half([12, 10, 8], [6, 4, 2, 0]);
        solve_p_q(u, v)
    }
}

/// `c·m`, entry by entry.
fn scaled(m: &DMatrix<f64>, c: f64) -> DMatrix<f64> {
    let mut out = m.clone();
    for x in out.as_mut_slice() {
        *x *= c;
    }
    out
}

/// `acc + c·m`, in place.
fn add_scaled(acc: &mut DMatrix<f64>, m: &DMatrix<f64>, c: f64) {
    for (a, x) in acc.as_mut_slice().iter_mut().zip(m.as_slice()) {
        *a += x * c;
    }
}

/// `acc + c·I`, in place — every entry, as adding the matrix c·I does (a −0 off the diagonal
/// becomes +0).
fn add_identity(acc: &mut DMatrix<f64>, c: f64) {
    let size = acc.nrows();
    for (k, a) in acc.as_mut_slice().iter_mut().enumerate() {
        *a += if k % size == k / size { c } else { 0.0 };
    }
}

/// The largest column sum of |m|: each column summed from the top, one entry at a time (the
/// bits of a fold), four columns side by side so that their additions overlap instead of each
/// waiting on the one before.
pub(crate) fn one_norm(m: &DMatrix<f64>) -> f64 {
    let size = m.nrows().max(1);
    let columns = m.as_slice().chunks_exact(size * 4);
    let rest = columns.remainder();
    let mut largest = 0.0f64;
    for four in columns {
        let (first, second) = four.split_at(2 * size);
        let (c0, c1) = first.split_at(size);
        let (c2, c3) = second.split_at(size);
        let mut sums = [0.0f64; 4];
        for (((a, b), c), d) in c0.iter().zip(c1).zip(c2).zip(c3) {
            sums[0] += a.abs();
            sums[1] += b.abs();
            sums[2] += c.abs();
            sums[3] += d.abs();
        }
        largest = sums.into_iter().fold(largest, f64::max);
    }
    rest.chunks(size)
        .map(|column| column.iter().fold(0.0, |sum, x| sum + x.abs()))
        .fold(largest, f64::max)
}

/// `fn name(args) -> R` that runs `body(args)` compiled twice — for the compiler's baseline
/// and, as `avx`, with AVX enabled — and calls the AVX one where the processor has it. `body`
/// must be `#[inline(always)]`, so that each copy is compiled with its own instructions. The
/// loops then take four `f64` a step instead of two, each lane doing the scalar code's
/// operations in the same order; the compiler forms no fused multiply-add, so the bits are the
/// same (the test `avx_and_baseline_agree_bit_for_bit`).
macro_rules! with_avx {
    ($(#[$doc:meta])* fn $name:ident / $avx:ident / $body:ident ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $(#[$doc])*
        fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if super::cpu::features().avx {
                #[allow(unsafe_code)]
                // SAFETY: the processor has AVX, checked just above.
                return unsafe { $avx($($arg),*) };
            }
            $body($($arg),*)
        }

        #[doc = concat!("[`", stringify!($body), "`] compiled for AVX ([`with_avx`]).")]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx")]
        fn $avx($($arg: $ty),*) -> $ret {
            $body($($arg),*)
        }
    };
}

with_avx! {
    /// ℓ(X, m): the extra squarings the backward error bound asks for, from
    /// ‖ |X|^(2m+1) ‖₁ / ‖X‖₁ (Al-Mohy and Higham's equation (5.1)); the norm is
    /// max(1ᵀ|X|^(2m+1)), one vector times |X| 2m + 1 times.
    fn ell / ell_avx / ell_body(a: &DMatrix<f64>, m: usize) -> u64
}

/// [`ell`] for whichever instruction set its caller is compiled for.
#[inline(always)]
fn ell_body(a: &DMatrix<f64>, m: usize) -> u64 {
    let size = a.nrows();
    // |X|ᵀ, column-major: its column j is row j of |X|, so v ← |X|ᵀ v is a sum of columns
    let abs_t = a.transpose().map(f64::abs);
    let mut v = vec![1.0f64; size];
    let mut next = vec![0.0f64; size];
    for _ in 0..2 * m + 1 {
        for (j, column) in abs_t.as_slice().chunks(size).enumerate() {
            let vj = v[j];
            if j == 0 {
                for (y, x) in next.iter_mut().zip(column) {
                    *y = x * vj;
                }
            } else {
                for (y, x) in next.iter_mut().zip(column) {
                    *y += x * vj;
                }
            }
        }
        std::mem::swap(&mut v, &mut next);
    }
    let norm = v[1..].iter().fold(v[0], |m, &x| m.max(x));
    if norm == 0.0 {
        return 0;
    }
    let factorial = |k: usize| (1..=k as u128).product::<u128>();
    let m_factorial = factorial(m);
    let choose_2m_m = factorial(2 * m) / (m_factorial * m_factorial);
    let abs_c_recip = choose_2m_m * factorial(2 * m + 1);
    let alpha = norm / one_norm(a) / abs_c_recip as f64;
    let u = 2_f64.powf(-53.0);
    let value = ((alpha / u).log2() / (2.0 * m as f64)).ceil();
    if value > 0.0 {
        value as u64
    } else {
        0
    }
}

with_avx! {
    /// R with (V − U) R = U + V, by LU factorisation with partial pivoting; `None` when a pivot
    /// is zero.
    fn solve_p_q / solve_p_q_avx / solve_p_q_body(u: DMatrix<f64>, v: DMatrix<f64>) -> Option<DMatrix<f64>>
}

/// [`solve_p_q`] for whichever instruction set its caller is compiled for.
#[inline(always)]
fn solve_p_q_body(u: DMatrix<f64>, v: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let size = u.nrows();
    // the right-hand sides P = U + V row by row (Pᵀ, made at once: Pᵀ's columns are P's rows):
    // each row operation then runs over all of them at once, in the order nalgebra gives each
    // column
    let mut rows = DMatrix::from_fn(size, size, |i, j| u[(j, i)] + v[(j, i)]);
    let mut q = v;
    for (x, y) in q.as_mut_slice().iter_mut().zip(u.as_slice()) {
        *x -= y;
    }
    drop(u);
    let swaps = factorise(q.as_mut_slice(), size)?;
    let x = rows.as_mut_slice();
    for &(i, piv) in &swaps {
        for k in 0..size {
            x.swap(i * size + k, piv * size + k);
        }
    }
    let lu = q.as_slice();
    // every diagonal entry of U is a pivot `factorise` found nonzero: the divisions are safe
    // the rows in blocks of TILE_ROWS, then single rows; the entries of a row in strips
    let blocks = spans(size, &[TILE_ROWS, 1]);
    let strips = spans(size, &[TILE_LANES, HALF_LANES, 1]);
    // L y = b, unit diagonal: the blocks from the top, each row taken from the rows above it
    for &(first, count) in &blocks {
        solve_block(Substitution::Forward, x, lu, size, (first, count), &strips);
    }
    // U x = y, the blocks from the bottom, each row taken from the rows below it, then divided
    for &(first, count) in blocks.iter().rev() {
        solve_block(Substitution::Backward, x, lu, size, (first, count), &strips);
    }
    // R = (Pᵀ solved)ᵀ, transposed where it lies
    rows.transpose_mut();
    Some(rows)
}

/// Rows a tile of the triangular solves takes at once, and the right-hand sides (entries of a
/// row of Pᵀ) it takes at once: 4 × 8 entries, eight AVX registers, kept in registers while
/// every earlier row is taken from them.
const TILE_ROWS: usize = 4;
/// See [`TILE_ROWS`]; a strip of half as many serves the last columns, then single ones.
const TILE_LANES: usize = 8;
/// See [`TILE_LANES`].
const HALF_LANES: usize = 4;

/// `0..size` cut into spans (start, length): as many of `lengths[0]` as fit, then of
/// `lengths[1]` in what is left, and so on (the last length 1, so that every index is covered).
fn spans(size: usize, lengths: &[usize]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for &length in lengths {
        while start + length <= size {
            spans.push((start, length));
            start += length;
        }
    }
    spans
}

/// Which of the two triangular solves a tile takes part in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Substitution {
    /// L y = b, from the top ([`forward_tile`]).
    Forward,
    /// U x = y, from the bottom ([`backward_tile`]).
    Backward,
}

/// The tile of `R` rows from `first` and `W` entries from `start`, in the substitution `way`.
#[inline(always)]
fn tile<const R: usize, const W: usize>(
    way: Substitution,
    x: &mut [f64],
    lu: &[f64],
    size: usize,
    first: usize,
    start: usize,
) {
    match way {
        Substitution::Forward => forward_tile::<R, W>(x, lu, size, first, start),
        Substitution::Backward => backward_tile::<R, W>(x, lu, size, first, start),
    }
}

/// Every strip of `strips` in the block of `count` rows from `first` (a full block of
/// [`TILE_ROWS`] or a single row), in the substitution `way`.
#[inline(always)]
fn solve_block(
    way: Substitution,
    x: &mut [f64],
    lu: &[f64],
    size: usize,
    (first, count): (usize, usize),
    strips: &[(usize, usize)],
) {
    for &(start, width) in strips {
        match (count == TILE_ROWS, width) {
            (true, TILE_LANES) => tile::<TILE_ROWS, TILE_LANES>(way, x, lu, size, first, start),
            (true, HALF_LANES) => tile::<TILE_ROWS, HALF_LANES>(way, x, lu, size, first, start),
            (true, _) => tile::<TILE_ROWS, 1>(way, x, lu, size, first, start),
            (false, TILE_LANES) => tile::<1, TILE_LANES>(way, x, lu, size, first, start),
            (false, HALF_LANES) => tile::<1, HALF_LANES>(way, x, lu, size, first, start),
            (false, _) => tile::<1, 1>(way, x, lu, size, first, start),
        }
    }
}

/// The `W` entries of `s` from `at`, as an array (no bounds checks in the loops over it).
#[inline(always)]
fn entries<const W: usize>(s: &[f64], at: usize) -> &[f64; W] {
    s[at..]
        .first_chunk::<W>()
        .unwrap_or_else(|| unreachable!("a tile lies inside its matrix"))
}

/// The rows `first..first + R` of Pᵀ (`x`, a row per column), in the entries `start..start +
/// W`, each take y + (−b)·l from every row i of `rows` in turn — b the row's entry, l the
/// factor's entry (i, row) — as the row-by-row elimination gives them, so the bits are the
/// same; the tile stays in registers while the rows stream past.
#[inline(always)]
fn take_rows<const R: usize, const W: usize>(
    x: &mut [f64],
    lu: &[f64],
    size: usize,
    (first, start): (usize, usize),
    rows: impl Iterator<Item = usize>,
) {
    let mut tile = [[0.0; W]; R];
    for (r, row) in tile.iter_mut().enumerate() {
        *row = *entries(x, (first + r) * size + start);
    }
    for i in rows {
        let b = entries::<W>(x, i * size + start);
        let l = entries::<R>(lu, i * size + first);
        for (row, &l) in tile.iter_mut().zip(l) {
            for (y, &b) in row.iter_mut().zip(b) {
                *y += -b * l;
            }
        }
    }
    for (r, row) in tile.iter().enumerate() {
        x[(first + r) * size + start..][..W].copy_from_slice(row);
    }
}

/// Forward substitution for the rows `first..first + R` of Pᵀ in the entries `start..start +
/// W`: the rows above taken in turn ([`take_rows`]), then the block's own rows.
#[inline(always)]
fn forward_tile<const R: usize, const W: usize>(
    x: &mut [f64],
    lu: &[f64],
    size: usize,
    first: usize,
    start: usize,
) {
    take_rows::<R, W>(x, lu, size, (first, start), 0..first);
    // inside the block, in place (the tile is indexed by constants only, so it stays in
    // registers): each row, once complete, taken from the rows below it
    for k in 0..R {
        let (done, below) = x.split_at_mut((first + k + 1) * size);
        let b = entries::<W>(done, (first + k) * size + start);
        let l = entries::<R>(lu, (first + k) * size + first);
        for (r, target) in below.chunks_mut(size).take(R - k - 1).enumerate() {
            let l = l[k + 1 + r];
            for (y, &b) in target[start..start + W].iter_mut().zip(b) {
                *y += -b * l;
            }
        }
    }
}

/// Back substitution for the rows `first..first + R` of Pᵀ in the entries `start..start + W`:
/// the rows below taken from the last up ([`take_rows`]), then the block's own rows, each
/// divided by its diagonal entry before it is taken, as the row-by-row elimination does it.
#[inline(always)]
fn backward_tile<const R: usize, const W: usize>(
    x: &mut [f64],
    lu: &[f64],
    size: usize,
    first: usize,
    start: usize,
) {
    take_rows::<R, W>(x, lu, size, (first, start), (first + R..size).rev());
    // inside the block, in place and from its last row up: divided, then taken from the rows
    // above it
    for k in (0..R).rev() {
        let diag = lu[(first + k) * size + first + k];
        let (above, rest) = x.split_at_mut((first + k) * size);
        let row = &mut rest[start..start + W];
        for y in row.iter_mut() {
            *y /= diag;
        }
        let u = entries::<R>(lu, (first + k) * size + first);
        for (r, target) in above[first * size..].chunks_mut(size).take(k).enumerate() {
            let u = u[r];
            for (y, &b) in target[start..start + W].iter_mut().zip(&*row) {
                *y += -b * u;
            }
        }
    }
}

/// The LU factorisation of the column-major `size × size` matrix `m` in place, the row swaps
/// returned in order; `None` when a column has no nonzero pivot.
#[inline(always)]
fn factorise(m: &mut [f64], size: usize) -> Option<Vec<(usize, usize)>> {
    let mut swaps = Vec::new();
    for i in 0..size {
        // the first entry of largest magnitude on or below the diagonal
        let column = &m[i * size..(i + 1) * size];
        let mut piv = i;
        for r in i + 1..size {
            if column[r].abs() > column[piv].abs() {
                piv = r;
            }
        }
        let diag = column[piv];
        if diag == 0.0 {
            return None;
        }
        if piv != i {
            swaps.push((i, piv));
            for c in m.chunks_mut(size) {
                c.swap(i, piv);
            }
        }
        let inv_diag = 1.0 / diag;
        let (left, right) = m.split_at_mut((i + 1) * size);
        let coeffs = &mut left[i * size + i + 1..];
        for x in coeffs.iter_mut() {
            *x *= inv_diag;
        }
        let coeffs = &*coeffs;
        for c in right.chunks_mut(size) {
            let pivot = c[i];
            for (y, l) in c[i + 1..].iter_mut().zip(coeffs) {
                *y += -pivot * l;
            }
        }
    }
    Some(swaps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Random matrices of orders 1–12 whose entries span the five degrees and the scalings
    /// (norms from 10⁻³ to 10²), some with zero rows as the zero-order hold's augmented matrix
    /// has.
    fn matrices() -> impl Strategy<Value = DMatrix<f64>> {
        (1usize..=12, -3i32..=2, 0usize..=3).prop_flat_map(|(n, scale, zero_rows)| {
            proptest::collection::vec(-1.0f64..1.0, n * n).prop_map(move |entries| {
                let mut m = DMatrix::from_vec(n, n, entries) * 10f64.powi(scale);
                for r in n.saturating_sub(zero_rows)..n {
                    m.row_mut(r).fill(0.0);
                }
                m
            })
        })
    }

    proptest! {
        #[test]
        fn equals_nalgebra_bit_for_bit(x in matrices()) {
            let ours = expm(&x).expect("nonsingular at these norms");
            let theirs = x.exp();
            for (a, b) in ours.iter().zip(theirs.iter()) {
                prop_assert_eq!(a.to_bits(), b.to_bits(), "{} against {}", a, b);
            }
        }

        /// The solve in tiles gives nalgebra's LU solve bit for bit — (V − U) R = U + V as its
        /// `exp` makes it — at orders up to 60: several blocks of rows, strips of eight, four
        /// and one column, and the single rows after the last block.
        #[test]
        fn solve_equals_nalgebra_lu_bit_for_bit(
            (n, entries) in (1usize..=60).prop_flat_map(|n| {
                (Just(n), proptest::collection::vec(-4.0f64..4.0, 2 * n * n))
            }),
        ) {
            let u = DMatrix::from_column_slice(n, n, &entries[..n * n]);
            let v = DMatrix::from_column_slice(n, n, &entries[n * n..]);
            let theirs = (&v - &u).lu().solve(&(&u + &v));
            let ours = solve_p_q(u, v);
            prop_assert_eq!(theirs.is_some(), ours.is_some());
            if let (Some(t), Some(o)) = (theirs, ours) {
                for (x, y) in t.iter().zip(o.iter()) {
                    prop_assert_eq!(x.to_bits(), y.to_bits(), "{} against {}", x, y);
                }
            }
        }

        /// The code compiled for AVX and the baseline's give the same bits, the solve and ℓ
        /// both, at orders up to 40 (where the AVX loops run whole vectors and a remainder);
        /// on a processor without AVX there is nothing to compare.
        #[cfg(target_arch = "x86_64")]
        #[test]
        fn avx_and_baseline_agree_bit_for_bit(
            (n, entries) in (1usize..=40).prop_flat_map(|n| {
                (Just(n), proptest::collection::vec(-4.0f64..4.0, 2 * n * n))
            }),
            m in prop_oneof![Just(3usize), Just(5), Just(7), Just(9), Just(13)],
        ) {
            if !std::arch::is_x86_feature_detected!("avx") {
                return Ok(());
            }
            let u = DMatrix::from_column_slice(n, n, &entries[..n * n]);
            let v = DMatrix::from_column_slice(n, n, &entries[n * n..]);
            let baseline = solve_p_q_body(u.clone(), v.clone());
            #[allow(unsafe_code)]
            // SAFETY: the processor has AVX, checked above.
            let avx = unsafe { solve_p_q_avx(u.clone(), v) };
            prop_assert_eq!(baseline.is_some(), avx.is_some());
            if let (Some(b), Some(a)) = (baseline, avx) {
                for (x, y) in b.iter().zip(a.iter()) {
                    prop_assert_eq!(x.to_bits(), y.to_bits(), "{} against {}", x, y);
                }
            }
            #[allow(unsafe_code)]
            // SAFETY: as above.
            let ell_avx_value = unsafe { ell_avx(&u, m) };
            prop_assert_eq!(ell_body(&u, m), ell_avx_value);
        }
    }

    #[test]
    fn degree_seven_is_chosen_without_the_eighth_power_where_its_bound_decides() {
        // a rotation at norm 0.6 (d6 = 0.6 < θ7, and the bound (‖X⁶‖‖X²‖)^(1/8) = 0.6 too) and
        // one at 0.9504175, where the bound is within the margin of θ7 = 0.9504179: X⁸ formed,
        // the same choice
        let mut decided = Vec::new();
        for norm in [0.6, 0.950_417_5] {
            let x =
                DMatrix::from_row_slice(3, 3, &[0.0, norm, 0.0, -norm, 0.0, 0.0, 0.0, 0.0, 0.0]);
            let mut powers = Powers::new(&x);
            decided.push(d8_below(&mut powers, THETA_7));
            assert!(powers.even[3].is_none(), "X⁸ not formed for the bound");
            let (ours, choice, _) = expm_choosing(&x).expect("nonsingular");
            assert_eq!(choice.degree, 7, "at {norm}");
            let theirs = x.exp();
            assert!(ours
                .iter()
                .zip(theirs.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
        }
        assert_eq!(decided, [true, false]);
    }

    #[test]
    fn every_degree_is_reached_and_matches() {
        // a rotation generator at growing norms: degrees 3, 5, 7, 9 and 13 with squarings
        let mut chosen = Vec::new();
        for norm in [1e-3, 0.1, 0.5, 1.5, 3.0, 40.0, 600.0] {
            let x =
                DMatrix::from_row_slice(3, 3, &[0.0, norm, 0.0, -norm, 0.0, 0.0, 0.0, 0.0, 0.0]);
            let (ours, choice, _) = expm_choosing(&x).expect("nonsingular");
            chosen.push((choice.degree, choice.squarings > 0));
            let theirs = x.exp();
            assert!(ours
                .iter()
                .zip(theirs.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            // and it is the rotation
            assert!((ours[(0, 0)] - norm.cos()).abs() < 1e-12 * norm.max(1.0));
            assert!((ours[(0, 1)] - norm.sin()).abs() < 1e-12 * norm.max(1.0));
        }
        for degree in [3, 5, 7, 9, 13] {
            assert!(chosen.iter().any(|c| c.0 == degree), "{chosen:?}");
        }
        assert!(chosen.contains(&(13, true)), "{chosen:?}");
    }

    #[test]
    fn powers_beyond_f64_are_refused_at_once() {
        // ‖X⁸‖ overflows: before, the count of squarings could saturate and the loop run on
        for entries in [
            [1e40, 1.0, 1.0, 1e40],
            [1e60, -1e60, 1e60, 1e60],
            [0.0, 1e100, -1e100, 0.0],
            [0.0, 1e300, -1e300, 0.0],
        ] {
            let x = DMatrix::from_row_slice(2, 2, &entries);
            let started = std::time::Instant::now();
            // refused, or not finite (which the zero-order hold refuses)
            let e = expm(&x);
            assert!(
                e.is_none_or(|e| e.iter().any(|v| !v.is_finite())),
                "{entries:?}"
            );
            assert!(started.elapsed().as_secs_f64() < 1.0, "{entries:?}");
        }
        // large but within reach: a rotation by 10⁶ radians is still computed
        let x = DMatrix::from_row_slice(2, 2, &[0.0, 1e6, -1e6, 0.0]);
        let e = expm(&x).expect("within reach");
        assert!((e[(0, 0)] - 1e6f64.cos()).abs() < 1e-6, "{e}");
    }

    #[test]
    fn a_non_finite_matrix_is_refused_not_a_panic() {
        let x = DMatrix::from_row_slice(2, 2, &[f64::NAN, 0.0, 0.0, 1.0]);
        let _ = expm(&x);
        let x = DMatrix::from_row_slice(2, 2, &[f64::INFINITY, 1.0, 0.0, 1.0]);
        let _ = expm(&x);
    }
}
