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
//! instructions per entry building and evaluating a tree.

use crate::algebra::{small_ratio, Rational};
use crate::linalg::{Matrix, MAX_EXACT_ORDER};

/// `[…]` of integer fractions, or `None` when the text is not in the scanner's subset.
pub(crate) fn rational_matrix(input: &str) -> Option<Matrix<Rational>> {
    if input.len() > super::MAX_INPUT_LENGTH {
        return None;
    }
    let mut s = Scanner {
        bytes: input.as_bytes(),
        pos: 0,
    };
    s.blanks();
    s.eat(b'[')?;
    // one row per `;` and one more; the entries row after row in one buffer, made as large as
    // the matrix once the first row gives its width (no copy into the matrix afterwards)
    let rows = input.bytes().filter(|&b| b == b';').count() + 1;
    if rows > MAX_EXACT_ORDER {
        return None;
    }
    let mut data: Vec<Rational> = Vec::new();
    let mut width = 0;
    for row in 0..rows {
        s.row(&mut data)?;
        if row == 0 {
            width = data.len();
            if width > MAX_EXACT_ORDER {
                return None;
            }
            data.reserve_exact(width * (rows - 1));
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
    if s.pos != s.bytes.len() {
        return None;
    }
    Matrix::from_row_major(rows, width, data).ok()
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
    /// At most 18 decimal digits as a machine word.
    fn digits(&mut self) -> Option<i128> {
        let start = self.pos;
        let mut value: i128 = 0;
        while let Some(b @ b'0'..=b'9') = self.peek() {
            value = value * 10 + i128::from(b - b'0');
            self.pos += 1;
            if self.pos - start > 18 {
                return None;
            }
        }
        (self.pos > start).then_some(value)
    }
    /// `-?d+(/d+)?`, followed by a separator or the end of the row.
    fn entry(&mut self) -> Option<Rational> {
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
        Some(small_ratio(numerator, denominator))
    }
    /// Entries up to (not including) `;` or `]`, appended to `out`; at least one.
    fn row(&mut self, out: &mut Vec<Rational>) -> Option<()> {
        self.blanks();
        loop {
            out.push(self.entry()?);
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
    }
}
