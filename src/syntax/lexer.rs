//! Tokens with their columns and the whitespace around them (MATLAB's matrix rules need it).

use super::{SyntaxError, MAX_INPUT_LENGTH};

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    Number(String),
    Ident(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    Sqrt,
    LParen,
    RParen,
    LBrack,
    RBrack,
    Comma,
    Semi,
    Newline,
    End,
}

impl Tok {
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Number(n) => format!("the number {n}"),
            Tok::Ident(n) => format!("'{n}'"),
            Tok::Plus => "'+'".into(),
            Tok::Minus => "'-'".into(),
            Tok::Star => "'*'".into(),
            Tok::Slash => "'/'".into(),
            Tok::Caret => "'^'".into(),
            Tok::Sqrt => "'√'".into(),
            Tok::LParen => "'('".into(),
            Tok::RParen => "')'".into(),
            Tok::LBrack => "'['".into(),
            Tok::RBrack => "']'".into(),
            Tok::Comma => "','".into(),
            Tok::Semi => "';'".into(),
            Tok::Newline => "a line break".into(),
            Tok::End => "the end of the input".into(),
        }
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Token {
    pub tok: Tok,
    /// 1-based column of the first character.
    pub column: usize,
    /// Whether whitespace precedes the token.
    pub space_before: bool,
}

pub(crate) fn tokenize(input: &str) -> Result<Vec<Token>, SyntaxError> {
    let chars: Vec<char> = input.chars().collect();
    if chars.len() > MAX_INPUT_LENGTH {
        return Err(SyntaxError::TooLarge {
            column: 1,
            what: format!("an input of {} characters", chars.len()),
            limit: MAX_INPUT_LENGTH,
        });
    }
    let mut out = Vec::new();
    let mut i = 0;
    let mut space = false;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        let single = match c {
            ' ' | '\t' | '\r' => {
                space = true;
                i += 1;
                continue;
            }
            '\n' => Some(Tok::Newline),
            '+' => Some(Tok::Plus),
            '-' | '−' => Some(Tok::Minus),
            '*' | '·' | '×' => Some(Tok::Star),
            '/' => Some(Tok::Slash),
            '^' => Some(Tok::Caret),
            '√' => Some(Tok::Sqrt),
            '(' => Some(Tok::LParen),
            ')' => Some(Tok::RParen),
            '[' => Some(Tok::LBrack),
            ']' => Some(Tok::RBrack),
            ',' => Some(Tok::Comma),
            ';' => Some(Tok::Semi),
            _ => None,
        };
        if let Some(tok) = single {
            out.push(Token {
                tok,
                column,
                space_before: space,
            });
            space = false;
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // exponent: e or E, optional sign, digits
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            if text.matches('.').count() > 1 {
                return Err(SyntaxError::Unexpected {
                    column: start + 1 + text.find('.').unwrap_or(0) + 1,
                    expected: "a digit".into(),
                    found: "a second '.'".into(),
                });
            }
            out.push(Token {
                tok: Tok::Number(text),
                column,
                space_before: space,
            });
            space = false;
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            out.push(Token {
                tok: Tok::Ident(text),
                column,
                space_before: space,
            });
            space = false;
            continue;
        }
        return Err(SyntaxError::Unexpected {
            column,
            expected: "a number, a name, an operator or a bracket".into(),
            found: format!("'{c}'"),
        });
    }
    out.push(Token {
        tok: Tok::End,
        column: chars.len() + 1,
        space_before: space,
    });
    Ok(out)
}
