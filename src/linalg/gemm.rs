//! The matrix product A·B in `f64`, with the bits nalgebra's `gemm` gives it.
//!
//! **Algorithm.** Register tiles. C's rows go in groups of eight — one vector of eight `f64`:
//! one AVX-512 register, two AVX ones, four of the baseline's — and a tile of R groups × W
//! columns of C stays in registers while k runs along A's columns: each step loads the tile's
//! 8R entries of A's column k and takes them times each of B's W entries of row k. A is copied
//! once into columns padded with zero rows to whole groups, each starting on a cache line (a
//! vector load across two lines costs two); the padding rows' results are not stored. B's rows
//! are copied once per block of k, W entries of a row side by side. A group of rows goes over
//! every block of columns before the next, so its part of A stays in the first-level cache.
//!
//! **Identity.** nalgebra's `gemm(1, A, B, 0)`, and its `*` on matrices, make for `f64`:
//! * when one of C's or A's dimensions is at most 5 (nalgebra's `SMALL_DIM`), each column by
//!   `gemv`: c_ij = a_i0·b_0j, then c_ij ← a_ik·b_kj + c_ij for k = 1, 2, …, a rounded product
//!   and a rounded sum each;
//! * otherwise matrixmultiply's `dgemm`: k in blocks of 256 (its `kc`); each block's sum
//!   starts from +0 and takes the terms one at a time in k's order, each a fused multiply-add
//!   where matrixmultiply runs its AVX-512, AVX2-with-FMA or NEON kernel, else a rounded product
//!   and a rounded sum (its AVX and portable kernels); the first block's sum is the entry, each
//!   later block's is added to it; the entry is then times α = 1, which changes no bit.
//!
//! Here every entry takes the same chain, whatever the tile: the tiles change which entries
//! are computed side by side, never the order of one entry's terms. Property tests compare
//! [`product`] with nalgebra's `gemm` bit for bit on the machine they run on (shapes across
//! the small and the blocked cases), and every kernel the processor runs — the portable one,
//! AVX, AVX2 with FMA, AVX-512 — with a scalar reference of its chain.
//!
//! **Cost.** 2·m·k·p flops; C, A's padded copy and B's rows allocated. The first query of
//! the processor's features goes to the C library's answers ([`super::cpu`]): matrixmultiply's
//! goes to `cpuid`, which in a virtual machine costs more than a whole product of order 11.
//! Measured on the 2-core machine (AMD EPYC, AVX-512; square products in a warm loop, best of
//! five, two runs): 0.26–0.27 / 0.84–0.87 / 7.1–7.2 / 43.1 / 317 µs at order 11 / 21 / 51 /
//! 101 / 201, against matrixmultiply's 0.25–0.26 / 0.72 / 6.9 / 41.8 / 316 µs there: slower
//! by 0.01 to 1.3 µs a product, where the process saves 27–52 µs of `cpuid` once (`zoh` takes
//! about a dozen products). B's rows gathered row after row, instead of scattered column after
//! column, took order 101 from 45.5 to 43.5 µs; A's copy without zeroing it first, to 43.1.

use nalgebra::DMatrix;

/// matrixmultiply's block of k (`D_KC`): each block's sum starts from zero.
const K_BLOCK: usize = 256;
/// Whether the tiles run: on x86-64, where matrixmultiply's first product asks `cpuid` which
/// kernel to run. Elsewhere nalgebra's own product makes the same bits without that cost (the
/// browser's module has no feature to ask about, and stays as small as it was).
const OWN_TILES: bool = cfg!(target_arch = "x86_64");
/// nalgebra's `SMALL_DIM`: at or below it in any dimension, `gemm` is column-by-column `gemv`.
const SMALL: usize = 5;
/// C's rows in one vector.
const LANES: usize = 8;

/// A·B, as `&a * &b` makes it.
///
/// # Panics
/// When A's columns are not B's rows (as nalgebra's product panics).
pub fn product(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let mut c = DMatrix::zeros(a.nrows(), b.ncols());
    product_into(&mut c, a, b);
    c
}

/// C ← A·B, as `c.gemm(1.0, a, b, 0.0)` makes it.
///
/// # Panics
/// When the shapes do not match (as nalgebra's `gemm` panics).
pub fn product_into(c: &mut DMatrix<f64>, a: &DMatrix<f64>, b: &DMatrix<f64>) {
    let (m, k, p) = (a.nrows(), a.ncols(), b.ncols());
    assert_eq!(k, b.nrows(), "product: A's columns are not B's rows");
    assert_eq!(
        (m, p),
        c.shape(),
        "product: C is not A's rows by B's columns"
    );
    if !OWN_TILES {
        c.gemm(1.0, a, b, 0.0);
        return;
    }
    let (cs, as_, bs) = (c.as_mut_slice(), a.as_slice(), b.as_slice());
    if k == 0 {
        cs.fill(0.0);
    } else if m <= SMALL || p <= SMALL || k <= SMALL {
        columns_by_gemv(cs, as_, bs, m, k);
    } else {
        blocked(cs, as_, bs, m, k);
    }
}

/// nalgebra's path for small dimensions: c_ij = a_i0·b_0j, then + a_ik·b_kj, each rounded.
fn columns_by_gemv(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    for (cj, bj) in c.chunks_exact_mut(m).zip(b.chunks_exact(k)) {
        for (i, entry) in cj.iter_mut().enumerate() {
            let mut sum = a[i] * bj[0];
            for t in 1..k {
                sum += a[t * m + i] * bj[t];
            }
            *entry = sum;
        }
    }
}

/// matrixmultiply's path, in the widest tiles the processor has.
fn blocked(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        let f = super::cpu::features();
        if f.avx512f {
            #[allow(unsafe_code)]
            // SAFETY: the processor has AVX-512F (and with it AVX2 and FMA), checked above
            return unsafe { blocked_avx512(c, a, b, m, k) };
        }
        if f.avx2_fma {
            #[allow(unsafe_code)]
            // SAFETY: the processor has AVX2 and FMA, checked above
            return unsafe { blocked_avx2_fma(c, a, b, m, k) };
        }
        if f.avx {
            #[allow(unsafe_code)]
            // SAFETY: the processor has AVX, checked above
            return unsafe { blocked_avx(c, a, b, m, k) };
        }
    }
    // without AVX matrixmultiply has no fused kernel either (its need AVX2 or AVX-512)
    portable(c, a, b, m, k)
}

/// The kernel for a tile: `$module::tile::<G, W>` for G the tile's groups (R, or 1 at the
/// last rows) and W its columns (1 to the widest), chosen at run time from its [`Tile`].
macro_rules! kernel {
    ($module:ident, $r:literal, [$($w:literal),+]) => {
        |c: &mut [f64], a: &[f64], b: &[f64], at: Tile| {
            if at.groups == $r {
                match at.width {
                    $($w => $module::tile::<$r, $w>(c, a, b, at),)+
                    _ => unreachable!("a tile no wider than its kernel's widest"),
                }
            } else {
                match at.width {
                    $($w => $module::tile::<1, $w>(c, a, b, at),)+
                    _ => unreachable!("a tile no wider than its kernel's widest"),
                }
            }
        }
    };
}

/// [`tiles`] in AVX-512 registers: 1 group × 16 columns, 16 of the 32 registers. Each of B's
/// entries is taken once a step, so it is broadcast within the multiply-add that takes it;
/// 3 groups × 8 columns, where each is taken three times and broadcast into a register first,
/// was 3 % slower at order 101, 24 columns 3 % slower too.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma,avx")]
fn blocked_avx512(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    tiles(
        c,
        a,
        b,
        m,
        k,
        1,
        16,
        kernel!(
            avx512,
            1,
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16]
        ),
    )
}

/// [`tiles`] in AVX registers with FMA: 1 group (two registers) × 6 columns, 12 of the 16.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx")]
fn blocked_avx2_fma(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    tiles(
        c,
        a,
        b,
        m,
        k,
        1,
        6,
        kernel!(avx2_fma, 1, [1, 2, 3, 4, 5, 6]),
    )
}

/// [`tiles`] in AVX registers without FMA: a product and a sum each term.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn blocked_avx(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    tiles(c, a, b, m, k, 1, 6, kernel!(avx, 1, [1, 2, 3, 4, 5, 6]))
}

/// C ← A·B over blocks of k, columns of W and row groups of R (see the module doc), each tile
/// by `kernel` in its shape. Inlined into each caller, so that each compiles for its own
/// instructions.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn tiles(
    c: &mut [f64],
    a: &[f64],
    b: &[f64],
    m: usize,
    k: usize,
    groups_per_tile: usize,
    columns_per_tile: usize,
    kernel: impl Fn(&mut [f64], &[f64], &[f64], Tile),
) {
    let (r, w) = (groups_per_tile, columns_per_tile);
    let p = c.len() / m;
    // A's rows padded with zeros to whole groups, each column starting on a cache line (a
    // vector load across two lines costs two)
    let rows = m.div_ceil(LANES) * LANES;
    let mut copy: Vec<f64> = Vec::with_capacity(rows * k + LANES);
    let offset = copy.as_ptr().align_offset(64).min(LANES);
    copy.resize(offset, 0.0);
    for column in a.chunks_exact(m) {
        copy.extend_from_slice(column);
        copy.resize(copy.len() + rows - m, 0.0);
    }
    let a = &copy[offset..];
    let groups = rows / LANES;
    // B's rows of a block of k, cut into blocks of w columns (the last narrower), each block
    // row after row
    let mut b_rows = vec![0.0; K_BLOCK.min(k) * p];
    let mut k0 = 0;
    while k0 < k {
        let k1 = (k0 + K_BLOCK).min(k);
        let depth = k1 - k0;
        let first = k0 == 0;
        let a_block = &a[k0 * rows..k1 * rows];
        for (start, columns) in (0..p).step_by(w).zip(b.chunks(k * w)) {
            let width = columns.len() / k;
            let block = &mut b_rows[start * depth..(start + width) * depth];
            // row after row, each row's entries gathered from the block's columns
            for (t, row) in block.chunks_exact_mut(width).enumerate() {
                for (x, column) in row.iter_mut().zip(columns.chunks_exact(k)) {
                    *x = column[k0 + t];
                }
            }
        }
        // a group of rows at a time over every block of columns: A's rows stay in the
        // first-level cache while B's blocks stream past
        let mut g = 0;
        while g < groups {
            let here = if groups - g >= r { r } else { 1 };
            let mut j = 0;
            while j < p {
                let width = w.min(p - j);
                let at = Tile {
                    m,
                    rows,
                    row: g * LANES,
                    column: j,
                    groups: here,
                    width,
                    first,
                };
                kernel(c, a_block, &b_rows[j * depth..(j + width) * depth], at);
                j += width;
            }
            g += here;
        }
        k0 = k1;
    }
}

/// [`tiles`] in the compiler's baseline, 1 group × 2 columns, each term a rounded product and
/// a rounded sum.
fn portable(c: &mut [f64], a: &[f64], b: &[f64], m: usize, k: usize) {
    tiles(c, a, b, m, k, 1, 2, kernel!(scalar, 1, [1, 2]))
}

/// Where a tile sits: C's row count and A's padded one, its first row and column, its groups
/// of rows and its columns, and whether its block of k is the first (its sums are the
/// entries) or a later one (added to them).
#[derive(Clone, Copy)]
struct Tile {
    m: usize,
    rows: usize,
    row: usize,
    column: usize,
    groups: usize,
    width: usize,
    first: bool,
}

/// The tile in scalars, for the compiler's baseline.
mod scalar {
    use super::{store, Tile, LANES};

    /// One tile of R groups × W columns over a block of k, in scalars: `a` holds A's columns of
    /// the block (`at.rows` entries each), `b` B's rows of the block, W entries each.
    #[inline(always)]
    pub(super) fn tile<const R: usize, const W: usize>(
        c: &mut [f64],
        a: &[f64],
        b: &[f64],
        at: Tile,
    ) {
        let mut sums = [[[0.0f64; LANES]; W]; R];
        for (column, b_row) in a.chunks_exact(at.rows).zip(b.chunks_exact(W)) {
            let column = &column[at.row..at.row + R * LANES];
            for w in 0..W {
                let s = b_row[w];
                for r in 0..R {
                    for l in 0..LANES {
                        let x = column[r * LANES + l];
                        sums[r][w][l] += x * s;
                    }
                }
            }
        }
        for w in 0..W {
            for r in 0..R {
                store(c, at, w, r, &sums[r][w]);
            }
        }
    }
}

/// A tile's sums into C: the entries of its first block of k, added to them after.
#[inline(always)]
fn store(c: &mut [f64], at: Tile, column: usize, group: usize, sums: &[f64; LANES]) {
    let start = (at.column + column) * at.m;
    let c_column = &mut c[start..start + at.m];
    let row = at.row + group * LANES;
    if row + LANES <= at.m {
        let entries = &mut c_column[row..row + LANES];
        if at.first {
            entries.copy_from_slice(sums);
        } else {
            for (entry, &sum) in entries.iter_mut().zip(sums) {
                *entry += sum;
            }
        }
        return;
    }
    for (l, &sum) in sums.iter().enumerate() {
        let i = at.row + group * LANES + l;
        if i < at.m {
            c_column[i] = if at.first { sum } else { sum + c_column[i] };
        }
    }
}

/// The tile in AVX-512 registers, one per group of eight rows; each term a fused
/// multiply-add.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx512 {
    use super::{store, Tile, LANES};
    use std::arch::x86_64::*;

    #[target_feature(enable = "avx512f,avx2,fma,avx")]
    pub(super) fn tile<const R: usize, const W: usize>(
        c: &mut [f64],
        a: &[f64],
        b: &[f64],
        at: Tile,
    ) {
        let mut sums = [[_mm512_setzero_pd(); W]; R];
        for (column, b_row) in a.chunks_exact(at.rows).zip(b.chunks_exact(W)) {
            let column = &column[at.row..at.row + R * LANES];
            let mut x = [_mm512_setzero_pd(); R];
            for r in 0..R {
                // SAFETY: `column` holds R × 8 entries, so eight from 8r on are in it
                x[r] = unsafe { _mm512_loadu_pd(column[r * LANES..].as_ptr()) };
            }
            for w in 0..W {
                let s = _mm512_set1_pd(b_row[w]);
                for r in 0..R {
                    sums[r][w] = _mm512_fmadd_pd(x[r], s, sums[r][w]);
                }
            }
        }
        for w in 0..W {
            for r in 0..R {
                let mut lanes = [0.0; LANES];
                // SAFETY: `lanes` holds eight entries
                unsafe { _mm512_storeu_pd(lanes.as_mut_ptr(), sums[r][w]) };
                store(c, at, w, r, &lanes);
            }
        }
    }
}

/// The tile in AVX registers, two per group of eight rows, written once for the two chains:
/// `term(x, s, sum)` is x·s joined to the sum.
#[cfg(target_arch = "x86_64")]
macro_rules! avx_tile {
    ($module:ident, $features:literal, $chain:literal, |$x:ident, $s:ident, $sum:ident| $term:expr) => {
        #[doc = concat!("The tile in AVX registers, ", $chain, ".")]
        #[allow(unsafe_code)]
        mod $module {
            use super::{store, Tile, LANES};
            use std::arch::x86_64::*;

            #[target_feature(enable = $features)]
            pub(super) fn tile<const R: usize, const W: usize>(
                c: &mut [f64],
                a: &[f64],
                b: &[f64],
                at: Tile,
            ) {
                let mut sums = [[[_mm256_setzero_pd(); 2]; W]; R];
                for (column, b_row) in a.chunks_exact(at.rows).zip(b.chunks_exact(W)) {
                    let column = &column[at.row..at.row + R * LANES];
                    let mut x = [[_mm256_setzero_pd(); 2]; R];
                    for r in 0..R {
                        for h in 0..2 {
                            // SAFETY: `column` holds R × 8 entries, so four from 8r + 4h on
                            // are in it
                            x[r][h] =
                                unsafe { _mm256_loadu_pd(column[r * LANES + 4 * h..].as_ptr()) };
                        }
                    }
                    for w in 0..W {
                        let $s = _mm256_set1_pd(b_row[w]);
                        for r in 0..R {
                            for h in 0..2 {
                                let ($x, $sum) = (x[r][h], sums[r][w][h]);
                                sums[r][w][h] = $term;
                            }
                        }
                    }
                }
                for w in 0..W {
                    for r in 0..R {
                        let mut lanes = [0.0; LANES];
                        for h in 0..2 {
                            // SAFETY: `lanes` holds eight entries, four from 4h on
                            unsafe { _mm256_storeu_pd(lanes[4 * h..].as_mut_ptr(), sums[r][w][h]) };
                        }
                        store(c, at, w, r, &lanes);
                    }
                }
            }
        }
    };
}

#[cfg(target_arch = "x86_64")]
avx_tile!(
    avx2_fma,
    "avx2,fma,avx",
    "each term a fused multiply-add",
    |x, s, sum| _mm256_fmadd_pd(x, s, sum)
);
#[cfg(target_arch = "x86_64")]
avx_tile!(
    avx,
    "avx",
    "each term a rounded product and a rounded sum",
    |x, s, sum| _mm256_add_pd(_mm256_mul_pd(x, s), sum)
);

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// How one term joins an entry's sum.
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    enum Chain {
        /// a·b + s, rounded once (a fused multiply-add).
        Fused,
        /// a·b rounded, then added to s and rounded.
        Separate,
    }

    /// The chain matrixmultiply's kernel for this processor takes (the module doc's rule).
    fn machine_chain() -> Chain {
        let f = crate::linalg::cpu::features();
        if f.avx512f || f.avx2_fma {
            Chain::Fused
        } else {
            Chain::Separate
        }
    }

    fn bits(m: &DMatrix<f64>) -> Vec<u64> {
        m.iter().map(|x| x.to_bits()).collect()
    }

    /// Each entry's chain written out, one term at a time.
    fn reference(a: &DMatrix<f64>, b: &DMatrix<f64>, chain: Chain) -> DMatrix<f64> {
        let (m, k, p) = (a.nrows(), a.ncols(), b.ncols());
        let small = m <= SMALL || p <= SMALL || k <= SMALL;
        DMatrix::from_fn(m, p, |i, j| {
            if small {
                return (1..k).fold(a[(i, 0)] * b[(0, j)], |s, t| a[(i, t)] * b[(t, j)] + s);
            }
            let mut entry = 0.0;
            for (n, k0) in (0..k).step_by(K_BLOCK).enumerate() {
                let block = (k0..(k0 + K_BLOCK).min(k)).fold(0.0, |s: f64, t| match chain {
                    Chain::Fused => a[(i, t)].mul_add(b[(t, j)], s),
                    Chain::Separate => a[(i, t)] * b[(t, j)] + s,
                });
                entry = if n == 0 { block } else { block + entry };
            }
            entry
        })
    }

    fn shapes() -> impl Strategy<Value = (DMatrix<f64>, DMatrix<f64>)> {
        (1usize..40, 1usize..40, 1usize..40).prop_flat_map(|(m, k, p)| {
            (
                proptest::collection::vec(-4.0f64..4.0, m * k),
                proptest::collection::vec(-4.0f64..4.0, k * p),
            )
                .prop_map(move |(x, y)| (DMatrix::from_vec(m, k, x), DMatrix::from_vec(k, p, y)))
        })
    }

    proptest! {
        #[test]
        fn equals_nalgebra_gemm_bit_for_bit((a, b) in shapes()) {
            let mut expected = DMatrix::zeros(a.nrows(), b.ncols());
            expected.gemm(1.0, &a, &b, 0.0);
            prop_assert_eq!(bits(&product(&a, &b)), bits(&expected));
            prop_assert_eq!(bits(&(&a * &b)), bits(&expected));
        }

        #[test]
        fn each_tile_takes_the_machines_chain((a, b) in shapes()) {
            let expected = reference(&a, &b, machine_chain());
            prop_assert_eq!(bits(&product(&a, &b)), bits(&expected));
        }

        #[test]
        #[allow(unsafe_code)]
        fn every_kernel_the_processor_runs_takes_its_chain((a, b) in shapes()) {
            let (m, k) = (a.nrows(), a.ncols());
            // the blocked chains alone (no small-dimension rule): shapes past it
            if m <= SMALL || k <= SMALL || b.ncols() <= SMALL {
                return Ok(());
            }
            let run = |kernel: fn(&mut [f64], &[f64], &[f64], usize, usize)| {
                let mut c = DMatrix::zeros(m, b.ncols());
                kernel(c.as_mut_slice(), a.as_slice(), b.as_slice(), m, k);
                bits(&c)
            };
            let separate = bits(&reference(&a, &b, Chain::Separate));
            let fused = bits(&reference(&a, &b, Chain::Fused));
            prop_assert_eq!(run(portable), separate.clone());
            let f = crate::linalg::cpu::features();
            if f.avx {
                // SAFETY: the processor has AVX, checked just above
                prop_assert_eq!(run(|c, a, b, m, k| unsafe { blocked_avx(c, a, b, m, k) }), separate);
            }
            if f.avx2_fma {
                // SAFETY: the processor has AVX2 and FMA, checked just above
                prop_assert_eq!(run(|c, a, b, m, k| unsafe { blocked_avx2_fma(c, a, b, m, k) }), fused.clone());
            }
            if f.avx512f {
                // SAFETY: the processor has AVX-512F, checked just above
                prop_assert_eq!(run(|c, a, b, m, k| unsafe { blocked_avx512(c, a, b, m, k) }), fused);
            }
        }
    }

    #[test]
    fn blocks_of_k_past_256_are_summed_as_matrixmultiply_sums_them() {
        // k = 600: three blocks; entries whose partial sums cancel, so the order shows
        let (m, k, p) = (13, 600, 9);
        let a = DMatrix::from_fn(m, k, |i, t| {
            ((i * 31 + t * 17) % 23) as f64 / 7.0 - 1.5 + if t % 256 == 0 { 1e16 } else { 0.0 }
        });
        let b = DMatrix::from_fn(k, p, |t, j| ((t * 13 + j * 5) % 19) as f64 / 3.0 - 2.9);
        let mut expected = DMatrix::zeros(m, p);
        expected.gemm(1.0, &a, &b, 0.0);
        assert_eq!(bits(&product(&a, &b)), bits(&expected));
        assert_eq!(bits(&expected), bits(&reference(&a, &b, machine_chain())));
        // and the test can tell: one chain over all of k differs, and so does the other kind
        // of term (on entries without the large ones, whose rounding would hide it)
        let one_chain = DMatrix::from_fn(m, p, |i, j| {
            (0..k).fold(0.0, |s: f64, t| match machine_chain() {
                Chain::Fused => a[(i, t)].mul_add(b[(t, j)], s),
                Chain::Separate => a[(i, t)] * b[(t, j)] + s,
            })
        });
        assert_ne!(bits(&expected), bits(&one_chain));
        let small = DMatrix::from_fn(m, k, |i, t| ((i * 31 + t * 17) % 23) as f64 / 7.0 - 1.5);
        let other = match machine_chain() {
            Chain::Fused => Chain::Separate,
            Chain::Separate => Chain::Fused,
        };
        assert_eq!(
            bits(&product(&small, &b)),
            bits(&reference(&small, &b, machine_chain()))
        );
        assert_ne!(
            bits(&product(&small, &b)),
            bits(&reference(&small, &b, other))
        );
    }

    #[test]
    fn a_zero_product_is_positive_zero_in_blocks_and_keeps_its_sign_in_gemv() {
        // −1·0 = −0: nalgebra's gemv keeps the first term's −0, matrixmultiply's sum from +0
        // does not
        for n in [3, 9] {
            let a = DMatrix::from_element(n, n, -1.0);
            let b = DMatrix::zeros(n, n);
            let mut expected = DMatrix::zeros(n, n);
            expected.gemm(1.0, &a, &b, 0.0);
            assert_eq!(bits(&product(&a, &b)), bits(&expected));
            assert_eq!(expected[(0, 0)].is_sign_negative(), n <= SMALL);
        }
    }
}
