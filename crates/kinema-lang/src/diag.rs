//! Diagnostics: what is wrong, where (a byte span), and a hint; rendered
//! with `ariadne` as `file:line:col`, the source line and an underline.

use ariadne::{Config, Label, Report, ReportKind, Source};

use crate::lexer::Span;

/// How serious a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// The program is not run.
    Error,
    /// Reported; the program still runs.
    Warning,
}

/// One problem in a program.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// Where, in bytes of the source.
    pub span: Span,
    /// What is wrong.
    pub message: String,
    /// What to do about it.
    pub hint: Option<String>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn error(span: Span, message: impl Into<String>) -> Self {
        Diagnostic { severity: Severity::Error, span, message: message.into(), hint: None }
    }

    /// A warning at `span`.
    pub fn warning(span: Span, message: impl Into<String>) -> Self {
        Diagnostic { severity: Severity::Warning, span, message: message.into(), hint: None }
    }

    /// The same with a hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Whether it stops the program.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// `file:line:col: error: message` on one line (line and column from 1,
    /// the column in characters).
    pub fn one_line(&self, file: &str, src: &str) -> String {
        let (line, col) = line_col(src, self.span.start);
        let kind = if self.is_error() { "error" } else { "warning" };
        format!("{file}:{line}:{col}: {kind}: {}", self.message)
    }

    /// The full report: `file:line:col`, the source line with the span
    /// underlined, the message and the hint (no colours).
    pub fn render(&self, file: &str, src: &str) -> String {
        let kind = if self.is_error() { ReportKind::Error } else { ReportKind::Warning };
        let span = clamp(src, &self.span);
        let mut report = Report::build(kind, (file, span.clone()))
            .with_config(Config::default().with_color(false))
            .with_message(&self.message)
            .with_label(Label::new((file, span)).with_message(short_label(&self.message)));
        if let Some(h) = &self.hint {
            report = report.with_help(h);
        }
        let mut out = Vec::new();
        let written = report.finish().write((file, Source::from(src)), &mut out);
        let mut text = String::from_utf8_lossy(&out).into_owned();
        if written.is_err() || text.is_empty() {
            text = self.one_line(file, src);
        }
        // ariadne prints the location as `[file:line:col]`; lead with the plain form too.
        format!("{}\n{text}", self.one_line(file, src))
    }
}

/// A label under the span: the message's first clause.
fn short_label(message: &str) -> String {
    message.split([';', ':']).next().unwrap_or(message).trim().to_string()
}

/// The span limited to the source, on character boundaries (ariadne counts characters).
fn clamp(src: &str, span: &Span) -> std::ops::Range<usize> {
    let to_chars = |b: usize| {
        let mut b = b.min(src.len());
        while !src.is_char_boundary(b) {
            b -= 1;
        }
        src[..b].chars().count()
    };
    let (s, e) = (to_chars(span.start), to_chars(span.end));
    s..e.max(s)
}

/// 1-based line and column (in characters) of byte `offset`.
pub fn line_col(src: &str, offset: usize) -> (usize, usize) {
    let mut o = offset.min(src.len());
    while !src.is_char_boundary(o) {
        o -= 1;
    }
    let before = &src[..o];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// Every diagnostic rendered, errors and warnings in source order, with a
/// closing count.
pub fn render_all(diags: &[Diagnostic], file: &str, src: &str) -> String {
    let mut sorted: Vec<&Diagnostic> = diags.iter().collect();
    sorted.sort_by_key(|d| d.span.start);
    let mut out = String::new();
    for d in &sorted {
        out.push_str(&d.render(file, src));
        out.push('\n');
    }
    let errors = diags.iter().filter(|d| d.is_error()).count();
    let warnings = diags.len() - errors;
    if errors > 0 {
        out.push_str(&format!("{file}: {errors} error(s), {warnings} warning(s); nothing was run\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let src = "PTP a\n  LIN bé\nWAIT 1s";
        assert_eq!(line_col(src, 0), (1, 1));
        assert_eq!(line_col(src, 8), (2, 3));
        assert_eq!(line_col(src, 15), (2, 9));
        assert_eq!(line_col(src, 16), (3, 1));
        assert_eq!(line_col(src, 1000), (3, 8));
    }

    #[test]
    fn rendering_shows_place_line_underline_and_hint() {
        let src = "PTP home\nWAIT 5mm\n";
        let d = Diagnostic::error(14..17, "expected a time, found a length").with_hint("write 5s");
        let text = d.render("prog.krl", src);
        assert!(text.starts_with("prog.krl:2:6: error: expected a time"), "{text}");
        assert!(text.contains("WAIT 5mm"), "{text}");
        assert!(text.contains("write 5s"), "{text}");
        // The underline sits under `5mm`.
        let line = text.lines().find(|l| l.contains("WAIT 5mm")).unwrap();
        let col = line.find("5mm").unwrap();
        let under = text.lines().skip_while(|l| !l.contains("WAIT 5mm")).nth(1).unwrap();
        assert!(
            under[col..].starts_with('─') || under[col..].starts_with('┬') || under[col..].starts_with('^'),
            "{text}"
        );
    }
}
