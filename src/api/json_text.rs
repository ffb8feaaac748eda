//! `--json`'s text: `serde_json::to_string_pretty`'s exact output, written without its
//! byte-by-byte escaping loop.
//!
//! A large exact answer is mostly long strings of digits and LaTeX (an order-40 reduced
//! observer's `--json` is 23 MB), and serde_json looks every byte up in its escape table: at
//! n = 20 a fifth of that command's instructions. Here a string is scanned sixteen bytes at a time for the bytes JSON
//! escapes (controls below 0x20, `"` and `\`), and the runs between them are copied whole.
//! The layout is serde_json's pretty printer's: two-space indent, `": "`, `[]`/`{}` when empty,
//! numbers by their own `Display` (the one serde_json serialises with). A property test
//! compares the two on random values.

use serde_json::Value;

/// `value` as `serde_json::to_string_pretty` writes it, appended to `out` (the report's text:
/// a large answer is not written into a string of its own and then copied).
pub fn write_pretty(out: &mut String, value: &Value) {
    write_value(out, value, 0);
}

fn indent(out: &mut String, level: usize) {
    for _ in 0..level {
        out.push_str("  ");
    }
}

fn write_value(out: &mut String, value: &Value, level: usize) {
    match value {
        Value::Null => out.push_str("null"),
        Value::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
        Value::Number(n) => out.push_str(&n.to_string()),
        Value::String(s) => write_string(out, s),
        Value::Array(items) => write_array(out, items.iter(), level, write_value),
        Value::Object(map) => write_object(out, map.iter(), level, |out, _, item, level| {
            write_value(out, item, level);
        }),
    }
}

/// `[…]` in the pretty layout, each item written by `write` at the items' level.
fn write_array<T>(
    out: &mut String,
    items: impl ExactSizeIterator<Item = T>,
    level: usize,
    mut write: impl FnMut(&mut String, T, usize),
) {
    if items.len() == 0 {
        out.push_str("[]");
        return;
    }
    out.push('[');
    for (i, item) in items.enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        indent(out, level + 1);
        write(out, item, level + 1);
    }
    out.push('\n');
    indent(out, level);
    out.push(']');
}

/// `{…}` in the pretty layout, each value written by `write` (given its key) at the entries'
/// level.
fn write_object<'a>(
    out: &mut String,
    entries: impl ExactSizeIterator<Item = (&'a String, &'a Value)>,
    level: usize,
    mut write: impl FnMut(&mut String, &'a str, &'a Value, usize),
) {
    if entries.len() == 0 {
        out.push_str("{}");
        return;
    }
    out.push('{');
    for (i, (key, item)) in entries.enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        indent(out, level + 1);
        write_string(out, key);
        out.push_str(": ");
        write(out, key, item, level + 1);
    }
    out.push('\n');
    indent(out, level);
    out.push('}');
}

/// `value` as [`write_pretty`] writes it after each of `keys` was set (in the map's own order
/// of keys), the entry of such a key written by `fill(out, index, level)` instead of being made
/// a value first, `index` the key's last place in `keys` (a repeated key keeps its last value,
/// as setting them one after another leaves it): what a report writes straight into its text
/// (its steps, its float matrices). A value that is not an object is written alone.
fn write_pretty_filled(
    out: &mut String,
    mut value: Value,
    keys: &[&str],
    mut fill: impl FnMut(&mut String, usize, usize),
) {
    let Some(map) = value.as_object_mut() else {
        write_value(out, &value, 0);
        return;
    };
    // placeholders take the keys' places among the others
    for key in keys {
        map.insert((*key).into(), Value::Null);
    }
    write_object(out, map.iter(), 0, |out, key, item, level| {
        match keys.iter().rposition(|k| *k == key) {
            Some(index) => fill(out, index, level),
            None => write_value(out, item, level),
        }
    });
}

/// `value` with its key `"steps"` set to `steps`, as [`write_pretty`] writes the value after
/// `steps` were inserted (in the map's own order of keys), each step written from its own
/// strings ([`write_step`]): an order-40 reduced observer's steps are 20 MB, not copied whole.
pub fn write_pretty_with_steps(out: &mut String, value: Value, steps: &[crate::derivation::Step]) {
    write_pretty_filled(out, value, &["steps"], |out, _, level| {
        write_array(out, steps.iter(), level, write_step);
    });
}

/// A step as its `Serialize` makes it a value and [`write_value`] writes that: an object of
/// its five strings in the order of their keys (a JSON object's keys are sorted), each string
/// written from the step itself, not copied into a value first (an order-60 reduced
/// observer's steps are 105 MB).
fn write_step(out: &mut String, step: &crate::derivation::Step, level: usize) {
    let mut fields = [
        ("formula", &step.formula),
        ("input", &step.input),
        ("label", &step.label),
        ("latex", &step.latex),
        ("text", &step.text),
    ];
    fields.sort_by_key(|(key, _)| *key);
    out.push('{');
    for (i, (key, text)) in fields.iter().enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        indent(out, level + 1);
        write_string(out, key);
        out.push_str(": ");
        write_string(out, text);
    }
    out.push('\n');
    indent(out, level);
    out.push('}');
}

/// `value` with each `(key, matrix)` of `matrices` set as [`super::args::ExpMatrix::value`]
/// makes it, as [`write_pretty`] writes the value after they were inserted (in the map's own
/// order of keys). The entries are written as they are formatted: `{:e}`'s text has no byte
/// JSON escapes, so each string is its quotes around it.
pub fn write_pretty_with_exp_matrices(
    out: &mut String,
    value: Value,
    matrices: &[(&str, super::args::ExpMatrix<'_>)],
) {
    let keys: Vec<&str> = matrices.iter().map(|(key, _)| *key).collect();
    write_pretty_filled(out, value, &keys, |out, index, level| {
        let m = &matrices[index].1;
        let (rows, cols) = m.shape();
        write_array(out, 0..rows, level, |out, i, level| {
            write_array(out, 0..cols, level, |out, j, _| {
                out.push('"');
                crate::algebra::float_text::push_exp(out, m.get(i, j));
                out.push('"');
            });
        });
    });
}

/// Whether JSON escapes this byte.
#[inline]
fn special(b: u8) -> bool {
    b < 0x20 || b == b'"' || b == b'\\'
}

/// The index of the first byte JSON escapes at or after `from`.
fn next_special(bytes: &[u8], from: usize) -> Option<usize> {
    let mut at = from;
    while at + 16 <= bytes.len() {
        let chunk = &bytes[at..at + 16];
        // no early exit inside the chunk: the compiler checks sixteen bytes at once
        if chunk.iter().fold(false, |any, &b| any | special(b)) {
            return chunk.iter().position(|&b| special(b)).map(|i| at + i);
        }
        at += 16;
    }
    bytes[at..].iter().position(|&b| special(b)).map(|i| at + i)
}

fn write_string(out: &mut String, s: &str) {
    const HEX: &[u8; 16] = b"0123456789abcdef";
    let bytes = s.as_bytes();
    out.reserve(s.len() + 2);
    out.push('"');
    let mut start = 0;
    while let Some(i) = next_special(bytes, start) {
        out.push_str(&s[start..i]);
        match bytes[i] {
            b'"' => out.push_str("\\\""),
            b'\\' => out.push_str("\\\\"),
            0x08 => out.push_str("\\b"),
            0x09 => out.push_str("\\t"),
            0x0A => out.push_str("\\n"),
            0x0C => out.push_str("\\f"),
            0x0D => out.push_str("\\r"),
            b => {
                out.push_str("\\u00");
                out.push(char::from(HEX[usize::from(b >> 4)]));
                out.push(char::from(HEX[usize::from(b & 0xF)]));
            }
        }
        start = i + 1;
    }
    out.push_str(&s[start..]);
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn leaf() -> impl Strategy<Value = Value> {
        prop_oneof![
            Just(Value::Null),
            any::<bool>().prop_map(Value::Bool),
            any::<i64>().prop_map(Value::from),
            any::<u64>().prop_map(Value::from),
            any::<f64>()
                .prop_filter("finite", |x| x.is_finite())
                .prop_map(Value::from),
            // every escaped byte, multi-byte characters and long runs
            "[\\x00-\\x1f\"\\\\a-z0-9 √−é→\\x7f]{0,40}".prop_map(Value::String),
            "[0-9/\\n-]{0,200}".prop_map(Value::String),
        ]
    }

    fn value() -> impl Strategy<Value = Value> {
        leaf().prop_recursive(4, 64, 6, |inner| {
            prop_oneof![
                proptest::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
                proptest::collection::vec(("[a-z\"\\x01_]{0,6}", inner), 0..6)
                    .prop_map(|kv| Value::Object(kv.into_iter().collect())),
            ]
        })
    }

    proptest! {
        #[test]
        fn writes_what_serde_json_writes(v in value()) {
            let expected = serde_json::to_string_pretty(&v).unwrap();
            let mut written = String::from("before ");
            write_pretty(&mut written, &v);
            prop_assert_eq!(written, format!("before {expected}"));
        }

        /// The steps written into the text one at a time are the steps inserted into the
        /// value and written with it: at their key's place, replacing a `"steps"` already
        /// there, and a value that is not an object written alone.
        #[test]
        fn steps_written_in_place_are_steps_inserted(
            v in prop_oneof![
                value(),
                proptest::collection::vec(("[a-z_]{0,7}", leaf()), 0..6)
                    .prop_map(|kv| Value::Object(kv.into_iter().collect())),
            ],
            texts in proptest::collection::vec(
                proptest::collection::vec("[a-z\"\\\n √−]{0,12}", 5),
                0..4,
            ),
        ) {
            // each field its own text, so that a field written under another's key fails
            let steps: Vec<crate::derivation::Step> = texts
                .iter()
                .map(|t| {
                    serde_json::from_value(serde_json::json!({
                        "label": t[0], "formula": t[1], "text": t[2], "latex": t[3],
                        "input": t[4],
                    }))
                    .unwrap()
                })
                .collect();
            let mut expected = v.clone();
            if let Some(map) = expected.as_object_mut() {
                map.insert("steps".into(), serde_json::to_value(&steps).unwrap());
            }
            let mut inserted = String::new();
            write_pretty(&mut inserted, &expected);
            let mut streamed = String::new();
            write_pretty_with_steps(&mut streamed, v, &steps);
            prop_assert_eq!(streamed, inserted);
        }

        /// Float matrices written into the text as they are formatted are the matrices made
        /// values and inserted: at their keys' places, replacing entries already there, empty
        /// ones as `[]`, every kind of f64 (NaN, infinities, −0, subnormals).
        #[test]
        fn exp_matrices_written_in_place_are_matrices_inserted(
            v in prop_oneof![
                value(),
                proptest::collection::vec(("[a-z_]{0,7}", leaf()), 0..6)
                    .prop_map(|kv| Value::Object(kv.into_iter().collect())),
            ],
            keys in proptest::collection::vec("[a-z_]{0,7}", 0..4),
            shapes in proptest::collection::vec((0usize..4, 0usize..4), 4),
            bits in proptest::collection::vec(any::<u64>(), 16),
        ) {
            let mut keys = keys;
            keys.dedup();
            let entry = |i: usize, j: usize| {
                let x = f64::from_bits(bits[(4 * i + j) % bits.len()]);
                [x, f64::NAN, f64::NEG_INFINITY, -0.0][(i + j) % 4 * usize::from(i == 1)]
            };
            let dense: Vec<nalgebra::DMatrix<f64>> = shapes
                .iter()
                .map(|&(rows, cols)| nalgebra::DMatrix::from_fn(rows, cols, entry))
                .collect();
            let matrices: Vec<(&str, crate::api::args::ExpMatrix<'_>)> = keys
                .iter()
                .zip(&dense)
                .map(|(k, m)| (k.as_str(), crate::api::args::ExpMatrix::Dense(m)))
                .collect();
            let mut expected = v.clone();
            if let Some(map) = expected.as_object_mut() {
                for (k, m) in &matrices {
                    map.insert((*k).into(), m.value());
                }
            }
            let mut inserted = String::new();
            write_pretty(&mut inserted, &expected);
            let mut streamed = String::new();
            write_pretty_with_exp_matrices(&mut streamed, v, &matrices);
            prop_assert_eq!(streamed, inserted);
        }
    }
}
