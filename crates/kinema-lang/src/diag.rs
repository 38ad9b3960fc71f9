//! Diagnostics: what is wrong, where (a byte span), and a hint; rendered
//! with `ariadne` as `file:line:col`, the source line and an underline.

use ariadne::{Config, IndexType, Label, Report, ReportKind, Source};

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
        self.one_line_at(file, line_col(src, self.span.start))
    }

    /// [`Diagnostic::one_line`] with the line index of `src` built once by the caller
    /// (for many diagnostics of one source).
    pub fn one_line_in(&self, file: &str, src: &str, lines: &LineIndex) -> String {
        self.one_line_at(file, lines.line_col(src, self.span.start))
    }

    fn one_line_at(&self, file: &str, (line, col): (usize, usize)) -> String {
        let kind = if self.is_error() { "error" } else { "warning" };
        format!("{file}:{line}:{col}: {kind}: {}", self.message)
    }

    /// The full report: `file:line:col`, the source line with the span
    /// underlined, the message and the hint (no colours).
    pub fn render(&self, file: &str, src: &str) -> String {
        self.render_in(file, src, &Source::from(src), &LineIndex::new(src))
    }

    /// [`Diagnostic::render`] with the source's line tables built once by the caller, so
    /// rendering many diagnostics costs the length of their lines, not of the whole source each.
    fn render_in(&self, file: &str, src: &str, source: &Source<&str>, lines: &LineIndex) -> String {
        let kind = if self.is_error() { ReportKind::Error } else { ReportKind::Warning };
        let span = clamp(src, &self.span);
        // Byte offsets: ariadne turns them into columns within the line only.
        let mut report = Report::build(kind, (file, span.clone()))
            .with_config(Config::default().with_color(false).with_index_type(IndexType::Byte))
            .with_message(&self.message)
            .with_label(Label::new((file, span)).with_message(short_label(&self.message)));
        if let Some(h) = &self.hint {
            report = report.with_help(h);
        }
        let mut out = Vec::new();
        let one_line = self.one_line_at(file, lines.line_col(src, self.span.start));
        let written = report.finish().write((file, source), &mut out);
        let mut text = String::from_utf8_lossy(&out).into_owned();
        if written.is_err() || text.is_empty() {
            text = one_line.clone();
        }
        // ariadne prints the location as `[file:line:col]`; lead with the plain form too.
        format!("{one_line}\n{text}")
    }
}

/// A label under the span: the message's first clause.
fn short_label(message: &str) -> String {
    message.split([';', ':']).next().unwrap_or(message).trim().to_string()
}

/// The span limited to the source, on character boundaries (in bytes).
fn clamp(src: &str, span: &Span) -> std::ops::Range<usize> {
    let floor = |b: usize| {
        let mut b = b.min(src.len());
        while !src.is_char_boundary(b) {
            b -= 1;
        }
        b
    };
    let (s, e) = (floor(span.start), floor(span.end));
    s..e.max(s)
}

/// Where each line of a source starts, to turn byte offsets into lines and
/// columns in time proportional to the line, not to the whole source.
#[derive(Debug, Clone)]
pub struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    /// The line starts of `src`.
    pub fn new(src: &str) -> Self {
        let starts = std::iter::once(0).chain(src.match_indices('\n').map(|(i, _)| i + 1)).collect();
        LineIndex { starts }
    }

    /// 1-based line of byte `offset` (clamped to the source).
    pub fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&s| s <= offset).max(1)
    }

    /// 1-based line and column (in characters) of byte `offset` of `src`, the source
    /// this index was built from; as [`line_col`].
    pub fn line_col(&self, src: &str, offset: usize) -> (usize, usize) {
        let mut o = offset.min(src.len());
        while !src.is_char_boundary(o) {
            o -= 1;
        }
        let line = self.line(o);
        let start = self.starts[line - 1];
        (line, src[start..o].chars().count() + 1)
    }
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

/// Diagnostics [`render_all`] shows as full reports; any further ones get their
/// one-line form only (a program of thousands of errors still prints every place, fast).
pub const FULL_REPORTS: usize = 100;

/// Every diagnostic rendered, errors and warnings in source order, with a
/// closing count: the first [`FULL_REPORTS`] as full reports, the rest one line each.
pub fn render_all(diags: &[Diagnostic], file: &str, src: &str) -> String {
    let mut sorted: Vec<&Diagnostic> = diags.iter().collect();
    sorted.sort_by_key(|d| d.span.start);
    let source = Source::from(src);
    let lines = LineIndex::new(src);
    let mut out = String::new();
    for (k, d) in sorted.iter().enumerate() {
        if k < FULL_REPORTS {
            out.push_str(&d.render_in(file, src, &source, &lines));
        } else {
            if k == FULL_REPORTS {
                out.push_str(&format!("{file}: {} more diagnostic(s), one line each:\n", sorted.len() - FULL_REPORTS));
            }
            out.push_str(&d.one_line_in(file, src, &lines));
        }
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
        let index = LineIndex::new(src);
        for o in 0..=src.len() + 2 {
            assert_eq!(index.line_col(src, o), line_col(src, o), "offset {o}");
        }
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
