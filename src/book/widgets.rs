//! The book's interactive parts, as HTML the preprocessor writes into a chapter: answer fields
//! under each exercise, the per-student variant form and the playground. The page's script
//! (`book/owb-web/owb.js`) finds them by class and runs the workbench compiled to WebAssembly
//! (`web/`), so what a student sees in the browser is what `owb check` says.
//!
//! The HTML is one block without blank lines (Markdown would end the block there), and its
//! attributes escape `$` (the math preprocessor would read it as a formula).

use crate::exercise::AnswerKey;
use std::fmt::Write;

/// Text escaped for an HTML attribute or element, newlines kept as character references and
/// `$` hidden from the math preprocessor.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            '\n' => out.push_str("&#10;"),
            '$' => out.push_str("&#36;"),
            '\\' => out.push_str("&#92;"),
            '{' => out.push_str("&#123;"),
            '}' => out.push_str("&#125;"),
            '*' => out.push_str("&#42;"),
            '_' => out.push_str("&#95;"),
            '`' => out.push_str("&#96;"),
            c => out.push(c),
        }
    }
    out
}

/// What a part's answer looks like, for the field's placeholder: the syntax the checker reads.
fn placeholder(input: &str) -> &'static str {
    let t = input.trim();
    if t.starts_with('[') {
        if t.contains(';') {
            "a matrix, rows split by ; e.g. [1 2; 3 4], or a column [1; 2]"
        } else {
            "a row, e.g. [1 2]"
        }
    } else if t == "yes" || t == "no" || t == "true" || t == "false" {
        "yes or no"
    } else if t.contains('s') || t.contains('λ') {
        "a polynomial in s (or λ), e.g. s^2 + 9s + 20"
    } else {
        "a number, e.g. -3/4 or sqrt(2)"
    }
}

/// The answer fields of an exercise: one per part, a check button, the feedback in place and the
/// answer file `owb check` reads (kept up to date as the student types). `toml` is the exercise
/// file itself, which the browser checks against.
pub fn exercise_form(id: &str, toml: &str, key: &AnswerKey) -> String {
    let mut out = format!(
        "<div class=\"owb-exercise\" data-exercise-id=\"{}\" data-exercise=\"{}\">",
        escape(id),
        escape(toml)
    );
    out.push_str("<p class=\"owb-note\">Type your answers in the workbench's syntax (MATLAB-style matrices, <code>sqrt(2)</code>, fractions such as <code>-3/4</code>, polynomials in <code>s</code> or <code>λ</code>, <code>yes</code>/<code>no</code>) and press <em>Check</em>: each part's feedback appears under it, computed in your browser by the same code as <code>owb check</code>.</p>");
    for p in &key.parts {
        let field = format!("owb-{}-{}", escape(id), escape(&p.spec.id));
        let _ = write!(
            out,
            "<div class=\"owb-part\" data-part=\"{part}\"><label for=\"{field}\"><code>{part}</code> — {prompt} <span class=\"owb-points\">({points} point{plural})</span></label><input type=\"text\" class=\"owb-answer\" id=\"{field}\" spellcheck=\"false\" autocomplete=\"off\" autocapitalize=\"off\" placeholder=\"{hint}\"><div class=\"owb-read\"></div><div class=\"owb-feedback\" aria-live=\"polite\"></div></div>",
            part = escape(&p.spec.id),
            prompt = escape(&p.spec.prompt),
            points = p.spec.points,
            plural = if p.spec.points == 1.0 { "" } else { "s" },
            hint = escape(placeholder(&p.value.input())),
        );
    }
    let hints: Vec<String> = key
        .parts
        .iter()
        .filter_map(|p| {
            crate::exercise::hint(p.spec.ask).map(|h| {
                format!(
                    "<li><code>{}</code>: {}</li>",
                    escape(&p.spec.id),
                    escape(h)
                )
            })
        })
        .collect();
    if !hints.is_empty() {
        let _ = write!(
            out,
            "<details class=\"owb-hints\"><summary>Hints</summary><ul>{}</ul></details>",
            hints.join("")
        );
    }
    out.push_str("<div class=\"owb-actions\"><button type=\"button\" class=\"owb-check\">Check</button> <span class=\"owb-score\" aria-live=\"polite\"></span></div>");
    let _ = write!(
        out,
        "<details class=\"owb-answer-file\"><summary>Your answers as a file for <code>owb check {}</code></summary><pre><code class=\"owb-answer-toml\"></code></pre></details>",
        escape(id)
    );
    out.push_str("<noscript>The answer fields need JavaScript; without it, check your answers with <code>owb check</code>.</noscript></div>");
    out
}

/// The per-student form: a student id in, the student's own generated exercise out, with answer
/// fields, checked in the page, and the answers to hand in as a file.
pub fn variant_form() -> String {
    "<div class=\"owb-variant\"><div class=\"owb-row\"><label>Your student id <input type=\"text\" class=\"owb-student\" spellcheck=\"false\" autocomplete=\"off\" placeholder=\"e.g. s123456\"></label> <label>Order <select class=\"owb-order\"><option value=\"2\">2</option><option value=\"3\" selected>3</option><option value=\"2..3\">2 or 3</option></select></label> <label>Exercise <select class=\"owb-kind\"><option value=\"pole-placement\">pole placement</option><option value=\"dead-beat\">dead-beat (discrete time)</option><option value=\"reduced-order\">reduced-order observer</option><option value=\"formula\">a gain as a formula (parameters a, w)</option></select></label> <label>Convention <select class=\"owb-convention\"><option value=\"a-kc\">A − KC</option><option value=\"a+lc\">A + LC</option></select></label> <button type=\"button\" class=\"owb-new-variant\">My exercise</button></div><div class=\"owb-variant-body\"></div><noscript>The variants need JavaScript; without it, <code>owb exercise new --student ID</code> generates the same exercise.</noscript></div>".to_string()
}

/// The playground: A and C in, a design chosen, the workbench's output and derivation out; and
/// the worked examples (`examples`: id and TOML), editable and verified in the page.
pub fn playground(examples: &[(String, String)]) -> String {
    let mut out = String::from("<div class=\"owb-playground\">");
    out.push_str("<div class=\"owb-grid\"><label>A <textarea class=\"owb-a\" rows=\"3\" spellcheck=\"false\">[2 -3; 4 -5]</textarea></label><label>C <textarea class=\"owb-c\" rows=\"3\" spellcheck=\"false\">[-3 2]</textarea></label></div>");
    out.push_str("<div class=\"owb-row\"><label>Desired <select class=\"owb-family\"><option value=\"poles\">poles</option><option value=\"poly\">polynomial</option><option value=\"repeated\">repeated root, time constant T</option><option value=\"butterworth\">Butterworth, time constant T</option><option value=\"bessel\">Bessel, delay T</option><option value=\"itae\">ITAE, time constant T</option></select></label> <input type=\"text\" class=\"owb-desired\" value=\"-4, -5\" spellcheck=\"false\" aria-label=\"the desired poles, polynomial or time constant\"></div>");
    out.push_str("<div class=\"owb-row\"><label>Method <select class=\"owb-method\"><option>ackermann</option><option>bass-gura</option><option>canonical</option></select></label> <label>Convention <select class=\"owb-pconvention\"><option value=\"a-kc\">A − KC</option><option value=\"a+lc\">A + LC</option></select></label> <label><input type=\"checkbox\" class=\"owb-float\" checked> float check</label></div>");
    out.push_str("<div class=\"owb-actions\"><button type=\"button\" data-run=\"gain\">Observer gain</button> <button type=\"button\" data-run=\"observe\">Observability</button> <button type=\"button\" data-run=\"canonical\">Canonical form</button></div>");
    out.push_str("<div class=\"owb-command\"></div><div class=\"owb-math\"></div><pre class=\"owb-output\" aria-live=\"polite\"></pre>");
    any_command(&mut out);
    out.push_str(
        "<h3>Verify a worked example</h3><div class=\"owb-row\"><select class=\"owb-example\" aria-label=\"a worked example\">",
    );
    for (id, toml) in examples {
        let _ = write!(
            out,
            "<option value=\"{}\" data-toml=\"{}\">{}</option>",
            escape(id),
            escape(toml),
            escape(id)
        );
    }
    out.push_str("</select> <button type=\"button\" class=\"owb-verify\">Verify</button></div><textarea class=\"owb-example-toml\" rows=\"12\" spellcheck=\"false\" aria-label=\"the worked example as TOML, editable\"></textarea><pre class=\"owb-verify-output\" aria-live=\"polite\"></pre>");
    out.push_str("<noscript>The playground needs JavaScript; the same commands run as <code>owb gain</code>, <code>owb observe</code>, <code>owb canonical</code> and <code>owb verify</code>.</noscript></div>");
    out
}

/// Every command the browser runs, with a request to start from: `key = value` lines, the keys
/// named as the command line's flags (`true` for a flag without a value).
pub const ANY_COMMAND_EXAMPLES: [(&str, &str); 13] = [
    ("observe", "a = [0 1; -k/m -c/m]\nc = [0 1]"),
    ("canonical", "a = [2 -3; 4 -5]\nc = [-3 2]\nb = [1; 0]"),
    (
        "gain",
        "a = [0 1; -2 -3]\nc = [1 0]\nitae = 1/2\nmethod = bass-gura",
    ),
    (
        "feedback",
        "a = [0 1; 0 0]\nb = [0; 1]\npoly = s^2 + 2*zeta*w*s + w^2",
    ),
    (
        "discrete",
        "a = [1 1; 0 1]\nc = [1 0]\ndeadbeat = true\nestimator = current",
    ),
    ("zoh", "a = [0 1; 0 0]\nb = [0; 1]\nperiod = 1/10"),
    (
        "dlqe",
        "a = [1 1; 0 1]\nc = [1 0]\nqn = [1 0; 0 1]\nrn = [1]",
    ),
    (
        "reduced",
        "a = [0 1 0; 0 0 1; -1 -2 -3]\nc = [1 0 0]\npoles = -5, -6",
    ),
    ("detectable", "a = [-1 0; 0 -2]\nc = [1 0]\npoles = -5"),
    (
        "control",
        "tf = (s + 1)/(s^2 + 3s + 5)\nl = [6; 15]\nfeedback-poly = s^2 + 4s + 4",
    ),
    (
        "optimal",
        "a = [0 1 0; 0 0 1; -1 -2 -3]\nc = [1 0 0; 0 1 0]\npoles = -1, -2, -3\nstarts = 4",
    ),
    (
        "kalman",
        "a = [0 1; -2 -3]\nb = [0; 1]\nc = [1 0]\ninput-noise = 1\noutput-noise = 1/10",
    ),
    ("perfect", "a = [0 1; -2 -3]\nb = [0; 1]\nc = [1 0]"),
];

/// The playground's "any command" part: a command chosen, its request edited as `key = value`
/// lines, run by the same function as the buttons above.
fn any_command(out: &mut String) {
    out.push_str("<h3>Any command</h3><div class=\"owb-row\"><label>Command <select class=\"owb-any-command\">");
    for (command, fields) in ANY_COMMAND_EXAMPLES {
        let _ = write!(
            out,
            "<option value=\"{command}\" data-fields=\"{}\">{command}</option>",
            escape(fields)
        );
    }
    out.push_str(
        "</select></label> <button type=\"button\" class=\"owb-any-run\">Run</button></div>",
    );
    out.push_str("<label class=\"owb-any-label\">Request, one <code>key = value</code> per line (the keys are the command line's flags) <textarea class=\"owb-any-fields\" rows=\"6\" spellcheck=\"false\"></textarea></label>");
    out.push_str("<div class=\"owb-any-command-line\"></div><div class=\"owb-any-math\"></div><pre class=\"owb-any-output\" aria-live=\"polite\"></pre>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaped_text_has_no_blank_line_no_dollar_and_no_markup() {
        let e = escape("a\n\nb $x$ <i>\"q\"</i> & {{#owb}} *y* _z_ `c` \\d");
        assert!(!e.contains('\n') && !e.contains('$') && !e.contains('<') && !e.contains('"'));
        assert!(!e.contains('{') && !e.contains('*') && !e.contains('_') && !e.contains('`'));
        assert!(!e.contains('\\'));
    }
}
