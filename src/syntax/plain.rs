//! The common case of a matrix flag read without building expression trees: a bracketed
//! matrix of integers and integer fractions (`[8/50 -2/50; 0 1]`), as tools and scripts write
//! it. The scanner accepts only a strict subset of the full grammar — entries `-?d+(/d+)?`
//! separated by spaces, tabs or one comma, rows by `;` — and gives up (`None`) on anything else:
//! an operator between spaces (`1 - 2`, one entry), a name, a line break, a zero denominator,
//! ragged or empty rows, more than 18 digits, a size beyond the exact algorithms' limit. The
//! full parser then reads the text and reports what is wrong, so every error comes from one
//! place. Where the scanner answers, its matrix is the one the full parser builds (a property
//! test compares them on random text over the grammar's characters). Cost: one pass over the
//! bytes and one word gcd per fraction, where the full parser spent several thousand
//! instructions per entry building and evaluating a tree. A command computing in `f64` may keep
//! the entries as the words the text spells ([`WordFractions`]), without making the exact
//! fractions at all.

use crate::algebra::{rational_to_f64, small_ratio, words_to_f64, Rational};
use crate::linalg::{Matrix, MAX_EXACT_ORDER};

/// `[…]` of integer fractions, or `None` when the text is not in the scanner's subset.
pub(crate) fn rational_matrix(input: &str) -> Option<Matrix<Rational>> {
    let (rows, cols, data) = scan(input, exact)?;
    Matrix::from_row_major(rows, cols, data).ok()
}

/// `[…]` of integer fractions as the words the text spells (see [`WordFractions`]), or `None`
/// when the text is not in the scanner's subset.
pub(crate) fn word_fractions(input: &str) -> Option<WordFractions> {
    let (rows, cols, entries) = scan(input, |n, d| (n, d))?;
    Some(WordFractions {
        rows,
        cols,
        entries,
    })
}

/// The scanner: each entry `n/d` made by `entry(n, d)`, the entries row after row in one buffer
/// (made as large as the matrix once the first row gives its width); the rows and columns.
fn scan<T>(input: &str, entry: impl Fn(i64, i64) -> T) -> Option<(usize, usize, Vec<T>)> {
    if input.len() > super::MAX_INPUT_LENGTH {
        return None;
    }
    let mut s = Scanner {
        bytes: input.as_bytes(),
        pos: 0,
    };
    s.blanks();
    s.eat(b'[')?;
    // one row per `;` and one more
    let rows = count_byte(input.as_bytes(), b';') + 1;
    if rows > MAX_EXACT_ORDER {
        return None;
    }
    // room for the whole matrix at once, the first row's words counted ahead (a buffer grown
    // entry by entry reallocated its 64-byte fractions a few times: a tenth of a 10-state
    // `gain` above the process's start)
    let words = input[s.pos..]
        .bytes()
        .take_while(|&b| b != b';' && b != b']')
        .fold((0, true), |(count, apart), b| match b {
            b' ' | b'\t' | b',' => (count, true),
            _ => (count + usize::from(apart), false),
        })
        .0;
    let mut data = Vec::with_capacity(words.min(MAX_EXACT_ORDER) * rows);
    let mut width = 0;
    for row in 0..rows {
        s.row(&mut data, &entry)?;
        if row == 0 {
            width = data.len();
            if width > MAX_EXACT_ORDER {
                return None;
            }
            data.reserve_exact(width * rows - data.len());
        } else if data.len() != width * (row + 1) {
            // the rows after the first are as long (or the text is refused)
            return None;
        }
        s.blanks();
        match (s.next()?, row + 1 == rows) {
            (b';', false) | (b']', true) => {}
            _ => return None,
        }
    }
    s.blanks();
    (s.pos == s.bytes.len()).then_some((rows, width, data))
}

/// How many times `byte` occurs in `bytes`: counted in blocks of 255 (a byte's count), which
/// the compiler turns into sixteen or thirty-two comparisons at a time; a count kept in a
/// machine word took a fifth of a 100-state plant's scan.
fn count_byte(bytes: &[u8], byte: u8) -> usize {
    bytes
        .chunks(255)
        .map(|block| {
            let count = block.iter().fold(0u8, |n, &b| n + u8::from(b == byte));
            usize::from(count)
        })
        .sum()
}

/// A matrix of fractions `n/d` as the text spells them — not reduced, the denominator positive,
/// each part below 10¹⁸ — for a command that computes in `f64` and needs the exact values only
/// to decide whether it may ([`WordFractions::trace_is_nonzero`]); [`WordFractions::to_rational`]
/// is the matrix [`rational_matrix`] reads. It costs 16 bytes an entry where a `Rational` costs
/// 64 and two allocations.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct WordFractions {
    rows: usize,
    cols: usize,
    /// `(n, d)` row after row.
    entries: Vec<(i64, i64)>,
}

impl WordFractions {
    /// The number of rows.
    pub(crate) fn rows(&self) -> usize {
        self.rows
    }
    /// The number of columns.
    pub(crate) fn cols(&self) -> usize {
        self.cols
    }
    /// The exact matrix, each entry in lowest terms.
    pub(crate) fn to_rational(&self) -> Matrix<Rational> {
        Matrix::from_fn(self.rows, self.cols, |i, j| {
            let (n, d) = self.entries[i * self.cols + j];
            exact(n, d)
        })
    }
    /// Entry `(i, j)` as [`rational_to_f64`] gives the exact entry: the two words' quotient where
    /// it is correctly rounded ([`words_to_f64`]), otherwise through that function.
    pub(crate) fn f64_at(&self, i: usize, j: usize) -> f64 {
        let (n, d) = self.entries[i * self.cols + j];
        words_to_f64(n, d).unwrap_or_else(|| rational_to_f64(&exact(n, d)))
    }
    /// Whether the trace of the (square) matrix is proved nonzero
    /// ([`crate::linalg::modular::trace_is_nonzero`]); `false` means "not proved".
    pub(crate) fn trace_is_nonzero(&self) -> bool {
        self.rows == self.cols
            && crate::linalg::modular::trace_is_nonzero(
                (0..self.rows).map(|i| self.entries[i * self.cols + i]),
            )
    }
}

/// The fraction `n/d` in lowest terms, as the full parser reads it.
fn exact(n: i64, d: i64) -> Rational {
    small_ratio(n.into(), d.into())
}

struct Scanner<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Scanner<'_> {
    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }
    fn next(&mut self) -> Option<u8> {
        let b = self.peek()?;
        self.pos += 1;
        Some(b)
    }
    fn eat(&mut self, b: u8) -> Option<()> {
        (self.next()? == b).then_some(())
    }
    /// Spaces and tabs; whether there were any.
    fn blanks(&mut self) -> bool {
        let start = self.pos;
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.pos += 1;
        }
        self.pos > start
    }
    /// At most 18 decimal digits as a machine word (below 10¹⁸ < 2⁶³).
    #[inline(always)]
    fn digits(&mut self) -> Option<i64> {
        let start = self.pos;
        let mut value: i64 = 0;
        while let Some(b @ b'0'..=b'9') = self.peek() {
            if self.pos - start == 18 {
                return None;
            }
            value = value * 10 + i64::from(b - b'0');
            self.pos += 1;
        }
        (self.pos > start).then_some(value)
    }
    /// `-?d+(/d+)?`, followed by a separator or the end of the row: its numerator and
    /// denominator, as the text spells them. Inlined, as [`Scanner::digits`] is: called, each
    /// returned its `Option` through memory, which stalled every entry (the scan of a 100-state
    /// plant took twice as long).
    #[inline(always)]
    fn entry(&mut self) -> Option<(i64, i64)> {
        let negative = self.peek() == Some(b'-');
        if negative {
            self.pos += 1;
        }
        let numerator = self.digits()?;
        let denominator = if self.peek() == Some(b'/') {
            self.pos += 1;
            self.digits()?
        } else {
            1
        };
        if denominator == 0 {
            return None;
        }
        match self.peek() {
            Some(b' ' | b'\t' | b',' | b';' | b']') => {}
            _ => return None,
        }
        let numerator = if negative { -numerator } else { numerator };
        Some((numerator, denominator))
    }
    /// Entries up to (not including) `;` or `]`, each made by `make` and appended to `out`; at
    /// least one.
    fn row<T>(&mut self, out: &mut Vec<T>, make: &impl Fn(i64, i64) -> T) -> Option<()> {
        self.blanks();
        loop {
            let (n, d) = self.entry()?;
            out.push(make(n, d));
            let spaced = self.blanks();
            match self.peek()? {
                b';' | b']' => return Some(()),
                b',' => {
                    self.pos += 1;
                    self.blanks();
                }
                _ if spaced => {}
                _ => return None,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn full(input: &str) -> Option<Matrix<Rational>> {
        super::super::parse_matrix::<Rational>(input).ok()
    }

    #[test]
    fn reads_what_the_parser_reads() {
        for text in [
            "[8/50 -2/50; 0 1]",
            "[1,-2; 3, 4]",
            "  [ -1 2 ]  ",
            "[1 -2]",
            "[0/7]",
            "[007 1/003]",
            "[999999999999999999/2]",
        ] {
            let fast = rational_matrix(text);
            assert!(fast.is_some(), "{text}");
            assert_eq!(fast, full(text), "{text}");
        }
    }

    #[test]
    fn leaves_the_rest_to_the_parser() {
        for text in [
            "[1 - 2]",
            "[1-2]",
            "[1 2;]",
            "[1 2; 3]",
            "[1/0]",
            "[]",
            "1 2",
            "[1 2\n3 4]",
            "[a 1]",
            "[1/ 2]",
            "[+1]",
            "[1,,2]",
            "[1 2] x",
            "[1234567890123456789]",
            "[[1, 2], [3, 4]]",
            "[−1]",
        ] {
            assert_eq!(rational_matrix(text), None, "{text}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]
        #[test]
        fn agrees_with_the_parser(text in "[ \\[\\];,/0-9\t+-]{0,24}") {
            if let Some(m) = rational_matrix(&text) {
                prop_assert_eq!(Some(m), full(&text), "{}", text);
            }
        }

        #[test]
        fn agrees_on_well_formed_matrices(
            rows in proptest::collection::vec(
                proptest::collection::vec((-30i64..30, 1i64..40, 0usize..4), 3), 1..4)
        ) {
            let text = format!("[{}]", rows.iter().map(|r| r.iter().map(|(n, d, sep)| {
                let sep = [" ", ",", " , ", "\t"][*sep];
                format!("{n}/{d}{sep}")
            }).collect::<String>().trim_end_matches([' ', ',', '\t']).to_string()).collect::<Vec<_>>().join("; "));
            let fast = rational_matrix(&text);
            prop_assert!(fast.is_some(), "{}", text);
            prop_assert_eq!(fast, full(&text), "{}", text);
        }

        /// The count in blocks is the count: texts across several blocks, of the bytes the
        /// scanner meets.
        #[test]
        fn bytes_counted_in_blocks_are_counted(
            text in proptest::collection::vec(proptest::sample::select(b"0;1 /-;".to_vec()), 0..2000),
        ) {
            let one_by_one = text.iter().filter(|&&b| b == b';').count();
            prop_assert_eq!(count_byte(&text, b';'), one_by_one);
        }

        /// The word fractions are the exact matrix's entries: as fractions, as `f64`s (also past
        /// 2⁵³, where the quotient of the two words would round twice), and a trace proved
        /// nonzero is nonzero.
        #[test]
        fn word_fractions_are_the_exact_entries(
            entries in proptest::collection::vec(
                (-999_999_999_999_999_999i64..=999_999_999_999_999_999,
                 1i64..=999_999_999_999_999_999, 0u32..4), 9),
            small in proptest::prelude::any::<bool>(),
        ) {
            // small parts (the quotient's path) or any up to 18 digits (the exact path)
            let part = |x: i64, shrink: u32| if small { x % 10i64.pow(3 + 4 * shrink) } else { x };
            let words: Vec<(i64, i64)> = entries.iter()
                .map(|&(n, d, k)| (part(n, k), part(d, k).max(1)))
                .collect();
            let text = format!("[{}]", words.chunks(3).map(|r| r.iter()
                .map(|(n, d)| format!("{n}/{d}")).collect::<Vec<_>>().join(" "))
                .collect::<Vec<_>>().join("; "));
            let w = word_fractions(&text).expect("in the scanner's subset");
            let exact = rational_matrix(&text).expect("in the scanner's subset");
            prop_assert_eq!(&w.to_rational(), &exact);
            for i in 0..3 {
                for j in 0..3 {
                    // num-rational's own correctly rounded conversion: independent of the
                    // quotient of two words that f64_at and rational_to_f64 share
                    let want = num_traits::ToPrimitive::to_f64(exact.get(i, j)).expect("in range");
                    prop_assert_eq!(w.f64_at(i, j).to_bits(), want.to_bits(), "({}, {})", i, j);
                }
            }
            let trace = (0..3).fold(Rational::from_integer(0.into()), |s, i| s + exact.get(i, i));
            if w.trace_is_nonzero() {
                prop_assert!(trace != Rational::from_integer(0.into()));
            }
        }
    }
}
