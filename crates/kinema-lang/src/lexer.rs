//! Tokens of a program, each with its byte span in the source.
//!
//! Statements end at a newline or `;`; `//` starts a comment to the end of
//! the line. Keywords and names are case-insensitive (kept as written, compared
//! in lower case). A number may carry a unit written right after it or after
//! spaces (`50mm`, `50 mm`, `90 deg/s`, `2 m/s^2`, `50%`); the unit is part
//! of the number token.

use std::ops::Range;

use crate::diag::Diagnostic;

/// Byte range of a token or node in the source.
pub type Span = Range<usize>;

/// What a token is.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// A name or keyword (letters, digits, `_`, and `-` before a letter; starts with a letter or `_`).
    Ident(String),
    /// A number with its optional unit (lower case, e.g. `"mm"`, `"deg/s"`, `"%"`).
    Number(f64, Option<String>),
    /// `,`
    Comma,
    /// `=`
    Eq,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// End of a statement: a newline or `;`.
    End,
}

impl Tok {
    /// How the token is named in messages.
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Number(v, Some(u)) => format!("`{v}{u}`"),
            Tok::Number(v, None) => format!("`{v}`"),
            Tok::Comma => "`,`".into(),
            Tok::Eq => "`=`".into(),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::Plus => "`+`".into(),
            Tok::Minus => "`-`".into(),
            Tok::Star => "`*`".into(),
            Tok::Slash => "`/`".into(),
            Tok::End => "the end of the statement".into(),
        }
    }
}

/// A token and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    /// The token.
    pub tok: Tok,
    /// Its bytes in the source.
    pub span: Span,
}

/// Units a number may carry (lower case). Lengths, angles, times, a
/// percentage, and linear/angular velocities and accelerations.
pub const UNITS: &[&str] = &[
    "mm", "cm", "m", "deg", "rad", "s", "ms", "%", "mm/s", "m/s", "deg/s", "rad/s", "mm/s^2", "m/s^2", "deg/s^2",
    "rad/s^2",
];

/// Splits `src` into tokens. Never fails as a whole: characters that cannot
/// start a token are reported and skipped, so the parser still sees the rest.
/// Consecutive statement ends collapse into one.
pub fn lex(src: &str) -> (Vec<Token>, Vec<Diagnostic>) {
    let bytes = src.as_bytes();
    let mut toks: Vec<Token> = Vec::new();
    let mut diags = Vec::new();
    let mut i = 0;
    let push_end = |toks: &mut Vec<Token>, at: usize, len: usize| {
        if !matches!(toks.last(), None | Some(Token { tok: Tok::End, .. })) {
            toks.push(Token { tok: Tok::End, span: at..at + len });
        }
    };
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'\n' | b';' => {
                push_end(&mut toks, i, 1);
                i += 1;
            }
            b' ' | b'\t' | b'\r' => i += 1,
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b',' | b'=' | b'(' | b')' | b'+' | b'-' | b'*' | b'/' => {
                let tok = match c {
                    b',' => Tok::Comma,
                    b'=' => Tok::Eq,
                    b'(' => Tok::LParen,
                    b')' => Tok::RParen,
                    b'+' => Tok::Plus,
                    b'-' => Tok::Minus,
                    b'*' => Tok::Star,
                    _ => Tok::Slash,
                };
                toks.push(Token { tok, span: i..i + 1 });
                i += 1;
            }
            b'0'..=b'9' | b'.' => {
                let start = i;
                while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                    i += 1;
                }
                // Exponent: 1e-3, 2.5E+2.
                if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
                    let mut j = i + 1;
                    if j < bytes.len() && (bytes[j] == b'+' || bytes[j] == b'-') {
                        j += 1;
                    }
                    if j < bytes.len() && bytes[j].is_ascii_digit() {
                        while j < bytes.len() && bytes[j].is_ascii_digit() {
                            j += 1;
                        }
                        i = j;
                    }
                }
                let text = &src[start..i];
                let value = match text.parse::<f64>() {
                    Ok(v) if v.is_finite() => v,
                    _ => {
                        diags.push(
                            Diagnostic::error(start..i, format!("`{text}` is not a number"))
                                .with_hint("write numbers like 12, 0.5, 1e-3"),
                        );
                        f64::NAN
                    }
                };
                let (unit, end) = unit_after(src, i);
                i = end;
                toks.push(Token { tok: Tok::Number(value, unit), span: start..i });
            }
            b'%' => {
                diags.push(
                    Diagnostic::error(i..i + 1, "`%` must follow a number").with_hint("write a percentage as 50%"),
                );
                i += 1;
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                let start = i;
                i += 1;
                while i < bytes.len()
                    && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' || is_inner_dash(bytes, i))
                {
                    i += 1;
                }
                toks.push(Token { tok: Tok::Ident(src[start..i].to_string()), span: start..i });
            }
            _ => {
                // One whole character (it may be several bytes).
                let ch = src[i..].chars().next().expect("inside the string");
                let len = ch.len_utf8();
                diags.push(Diagnostic::error(i..i + len, format!("unexpected character `{}`", ch.escape_debug())).with_hint(
                    "statements are keywords, names, numbers with units, `,` `=` `(` `)` and arithmetic; `//` starts a comment",
                ));
                i += len;
            }
        }
    }
    push_end(&mut toks, src.len(), 0);
    (toks, diags)
}

/// A `-` inside a name (pose names such as `sing-q2-q3`): preceded by a
/// letter or digit of the name and followed by a letter. `p-1` is `p` minus
/// 1; a subtraction of two names needs spaces (`a - b`).
fn is_inner_dash(bytes: &[u8], i: usize) -> bool {
    bytes[i] == b'-'
        && i > 0
        && bytes[i - 1].is_ascii_alphanumeric()
        && bytes.get(i + 1).is_some_and(|b| b.is_ascii_alphabetic())
}

/// The unit after a number ending at `i` (spaces allowed before it), if the
/// text there is one of [`UNITS`] and does not continue as a name.
fn unit_after(src: &str, i: usize) -> (Option<String>, usize) {
    let bytes = src.as_bytes();
    let mut j = i;
    while j < bytes.len() && (bytes[j] == b' ' || bytes[j] == b'\t') {
        j += 1;
    }
    if bytes.get(j) == Some(&b'%') {
        return (Some("%".into()), j + 1);
    }
    // The longest unit that matches, case-insensitively, at j.
    let mut best: Option<&str> = None;
    for u in UNITS {
        let end = j + u.len();
        if end <= bytes.len()
            && src.is_char_boundary(end)
            && src[j..end].eq_ignore_ascii_case(u)
            && !bytes.get(end).is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_')
            && best.is_none_or(|b| b.len() < u.len())
        {
            best = Some(u);
        }
    }
    match best {
        Some(u) => (Some(u.to_string()), j + u.len()),
        None => (None, i),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(src: &str) -> Vec<Tok> {
        let (t, d) = lex(src);
        assert!(d.is_empty(), "{d:?}");
        t.into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn numbers_carry_their_units() {
        assert_eq!(
            toks("MOVEZ -50mm, 2 s"),
            vec![
                Tok::Ident("MOVEZ".into()),
                Tok::Minus,
                Tok::Number(50.0, Some("mm".into())),
                Tok::Comma,
                Tok::Number(2.0, Some("s".into())),
                Tok::End
            ]
        );
        assert_eq!(toks("90 deg/s")[0], Tok::Number(90.0, Some("deg/s".into())));
        assert_eq!(toks("2M/S^2")[0], Tok::Number(2.0, Some("m/s^2".into())));
        assert_eq!(toks("50 %")[0], Tok::Number(50.0, Some("%".into())));
        assert_eq!(toks("1e-3 m")[0], Tok::Number(1e-3, Some("m".into())));
        // `m` followed by more letters is a name, not the unit.
        assert_eq!(toks("3 mx")[..2], [Tok::Number(3.0, None), Tok::Ident("mx".into())]);
        // A unit that is not followed by `/s`: `m` then `/` then a name.
        assert_eq!(toks("2 m/x")[..3], [Tok::Number(2.0, Some("m".into())), Tok::Slash, Tok::Ident("x".into())]);
    }

    #[test]
    fn comments_newlines_and_names() {
        assert_eq!(
            toks("// a comment\nPTP home ; ; \n\n LIN p2 // end"),
            vec![
                Tok::Ident("PTP".into()),
                Tok::Ident("home".into()),
                Tok::End,
                Tok::Ident("LIN".into()),
                Tok::Ident("p2".into()),
                Tok::End
            ]
        );
        // A dash between letters is part of a name; before a digit it is a minus.
        assert_eq!(toks("lbr-iiwa")[0], Tok::Ident("lbr-iiwa".into()));
        assert_eq!(toks("p-1")[..3], [Tok::Ident("p".into()), Tok::Minus, Tok::Number(1.0, None)]);
    }

    #[test]
    fn bad_characters_are_reported_and_skipped() {
        let (t, d) = lex("PTP # home\n€");
        assert_eq!(d.len(), 2);
        assert_eq!(d[0].span, 4..5);
        assert_eq!(d[1].span, 11..14);
        assert_eq!(t[1].tok, Tok::Ident("home".into()));
    }
}
