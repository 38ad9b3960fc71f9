//! Recursive-descent parser. On a syntax error it records a diagnostic and
//! skips to the end of the statement, so one run reports every error; it
//! never panics and always terminates (every loop consumes a token).

use crate::ast::{BinOp, Expr, MotionKind, MotionOpts, Name, Program, Stmt, StmtKind, Target};
use crate::diag::Diagnostic;
use crate::lexer::{lex, Span, Tok, Token};

/// Statement keywords, for messages.
pub const KEYWORDS: &[&str] = &[
    "POS",
    "PTP",
    "LIN",
    "CIRC",
    "SPEED",
    "VEL",
    "ACC",
    "JVEL",
    "JACC",
    "PROFILE",
    "REDUNDANCY",
    "TOOL",
    "BASE",
    "WAIT",
    "PAUSE",
    "HOME",
    "LOOP",
    "FOR",
    "MOVEZ",
    "MOVETITA",
    "MOVEXY",
];

/// `LOOP`/`FOR` blocks nested deeper than this are an error, and so are
/// expressions nested deeper (keeps recursion, here and in the compiler, bounded).
pub const MAX_DEPTH: usize = 64;

/// Operators (`+ - * /` and signs) one statement's expressions may hold: a chain of
/// sums is a tree as deep as it is long, and the compiler walks it recursively.
pub const MAX_OPERATORS: usize = 1000;

/// Parses a program. The tree holds every statement that parsed; the
/// diagnostics every lexical and syntax error.
pub fn parse(src: &str) -> (Program, Vec<Diagnostic>) {
    let (tokens, mut diags) = lex(src);
    let mut p = Parser { toks: tokens, pos: 0, diags: Vec::new(), src_len: src.len(), parens: 0, operators: 0 };
    let stmts = p.block(None, 0);
    diags.append(&mut p.diags);
    (Program { stmts }, diags)
}

struct Parser {
    toks: Vec<Token>,
    pos: usize,
    diags: Vec<Diagnostic>,
    src_len: usize,
    /// Open parentheses around the expression being parsed.
    parens: usize,
    /// Operators in the statement being parsed.
    operators: usize,
}

type PResult<T> = Result<T, Diagnostic>;

fn is_kw(t: &Tok, kw: &str) -> bool {
    matches!(t, Tok::Ident(s) if s.eq_ignore_ascii_case(kw))
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.toks.get(self.pos)
    }

    fn peek_tok(&self) -> Option<&Tok> {
        self.peek().map(|t| &t.tok)
    }

    fn here(&self) -> Span {
        self.peek().map(|t| t.span.clone()).unwrap_or(self.src_len..self.src_len)
    }

    fn prev_end(&self) -> usize {
        if self.pos == 0 {
            0
        } else {
            self.toks[self.pos - 1].span.end
        }
    }

    fn bump(&mut self) -> Option<Token> {
        let t = self.toks.get(self.pos).cloned();
        if t.is_some() {
            self.pos += 1;
        }
        t
    }

    fn at_kw(&self, kw: &str) -> bool {
        self.peek_tok().is_some_and(|t| is_kw(t, kw))
    }

    fn at_end(&self) -> bool {
        matches!(self.peek_tok(), None | Some(Tok::End))
    }

    fn unexpected(&self, expected: &str) -> Diagnostic {
        let found = self.peek_tok().map(Tok::describe).unwrap_or_else(|| "the end of the program".into());
        Diagnostic::error(self.here(), format!("expected {expected}, found {found}"))
    }

    fn expect(&mut self, tok: Tok, expected: &str) -> PResult<Span> {
        if self.peek_tok() == Some(&tok) {
            Ok(self.bump().expect("peeked").span)
        } else {
            Err(self.unexpected(expected))
        }
    }

    /// Skips to just after the next statement end.
    fn sync(&mut self) {
        while let Some(t) = self.bump() {
            if t.tok == Tok::End {
                break;
            }
        }
    }

    /// Statements until `END` (when `opener` is the block's keyword span) or
    /// the end of the program.
    fn block(&mut self, opener: Option<(&str, Span)>, depth: usize) -> Vec<Stmt> {
        let mut stmts = Vec::new();
        loop {
            while self.peek_tok() == Some(&Tok::End) {
                self.bump();
            }
            let Some(tok) = self.peek() else {
                if let Some((kw, span)) = opener {
                    self.diags.push(
                        Diagnostic::error(span, format!("{kw} without END"))
                            .with_hint(format!("close the {kw} block with a line `END`")),
                    );
                }
                return stmts;
            };
            if is_kw(&tok.tok, "END") {
                let span = tok.span.clone();
                self.bump();
                if opener.is_some() {
                    if !self.at_end() {
                        self.diags.push(self.unexpected("the end of the line after END"));
                        self.sync();
                    }
                    return stmts;
                }
                self.diags.push(
                    Diagnostic::error(span, "END without LOOP or FOR")
                        .with_hint("remove it, or open the block it closes"),
                );
                self.sync();
                continue;
            }
            match self.statement(depth) {
                Ok(s) => {
                    stmts.push(s);
                    if !self.at_end() {
                        self.diags.push(self.unexpected("the end of the statement (a new line or `;`)"));
                        self.sync();
                    }
                }
                Err(d) => {
                    self.diags.push(d);
                    self.sync();
                }
            }
        }
    }

    fn name(&mut self, what: &str) -> PResult<Name> {
        match self.peek_tok() {
            Some(Tok::Ident(s)) => {
                let text = s.clone();
                let span = self.bump().expect("peeked").span;
                Ok(Name { key: text.to_ascii_lowercase(), text, span })
            }
            _ => Err(self.unexpected(what)),
        }
    }

    fn statement(&mut self, depth: usize) -> PResult<Stmt> {
        let kw_tok = self.peek().cloned().expect("caller checked");
        let Tok::Ident(word) = &kw_tok.tok else {
            return Err(self
                .unexpected("a statement keyword")
                .with_hint(format!("statements start with {}", KEYWORDS.join(", "))));
        };
        let keyword = kw_tok.span.clone();
        let upper = word.to_ascii_uppercase();
        self.operators = 0;
        self.bump();
        let kind = match upper.as_str() {
            "POS" => {
                let name = self.name("a position name")?;
                self.expect(Tok::Eq, "`=`")?;
                let value = self.target()?;
                StmtKind::Pos { name, value }
            }
            "PTP" | "LIN" => {
                let kind = if upper == "PTP" { MotionKind::Ptp } else { MotionKind::Lin };
                let relative = if self.at_kw("REL") {
                    self.bump();
                    true
                } else {
                    false
                };
                let target = self.target()?;
                let opts = self.motion_opts()?;
                StmtKind::Motion { kind, relative, target, opts }
            }
            "CIRC" => {
                let aux = self.target()?;
                self.expect(Tok::Comma, "`,` between the auxiliary point and the end point")?;
                let target = self.target()?;
                let opts = self.motion_opts()?;
                StmtKind::Circ { aux, target, opts }
            }
            "SPEED" => StmtKind::Speed(self.expr()?),
            "VEL" => StmtKind::Vel(self.expr()?),
            "ACC" => StmtKind::Acc(self.expr()?),
            "JVEL" => StmtKind::JVel(self.expr()?),
            "JACC" => StmtKind::JAcc(self.expr()?),
            "PROFILE" => StmtKind::Profile(self.name("a profile name (trapezoid, scurve, quintic, cubic)")?),
            "REDUNDANCY" => {
                let mode = self
                    .name("a policy (hold, track, manipulability, avoid-limits, auto) or `q3 =` / `psi =` an angle")?;
                let value = if self.peek_tok() == Some(&Tok::Eq) {
                    self.bump();
                    Some(self.expr()?)
                } else {
                    None
                };
                StmtKind::Redundancy { mode, value }
            }
            "TOOL" => StmtKind::Tool(self.target()?),
            "BASE" => StmtKind::Base(self.target()?),
            "WAIT" | "PAUSE" => StmtKind::Wait(self.expr()?),
            "HOME" => StmtKind::Home(if self.at_end() { None } else { Some(self.expr()?) }),
            "LOOP" => {
                let count = self.expr()?;
                let body = self.body("LOOP", keyword.clone(), depth)?;
                StmtKind::Loop { count, body }
            }
            "FOR" => {
                let var = self.name("a counter name")?;
                self.expect(Tok::Eq, "`=`")?;
                let from = self.expr()?;
                if !self.at_kw("TO") {
                    return Err(self.unexpected("TO"));
                }
                self.bump();
                let to = self.expr()?;
                let body = self.body("FOR", keyword.clone(), depth)?;
                StmtKind::For { var, from, to, body }
            }
            "MOVEZ" => {
                let dz = self.expr()?;
                self.expect(Tok::Comma, "`,` before the time")?;
                StmtKind::MoveZ { dz, time: self.expr()? }
            }
            "MOVETITA" => {
                let dtheta = self.expr()?;
                self.expect(Tok::Comma, "`,` before the time")?;
                StmtKind::MoveTita { dtheta, time: self.expr()? }
            }
            "MOVEXY" => {
                let dx = self.expr()?;
                self.expect(Tok::Comma, "`,` between x and y")?;
                let dy = self.expr()?;
                self.expect(Tok::Comma, "`,` before the time")?;
                StmtKind::MoveXy { dx, dy, time: self.expr()? }
            }
            _ => {
                let hint = suggestion(word)
                    .map(|k| format!("did you mean {k}?"))
                    .unwrap_or_else(|| format!("statements start with {}", KEYWORDS.join(", ")));
                return Err(Diagnostic::error(keyword, format!("unknown statement `{word}`")).with_hint(hint));
            }
        };
        let span = keyword.start..self.prev_end().max(keyword.end);
        Ok(Stmt { kind, span, keyword })
    }

    /// A block body: the rest of the opening line must be empty.
    fn body(&mut self, kw: &str, keyword: Span, depth: usize) -> PResult<Vec<Stmt>> {
        if !self.at_end() {
            return Err(self.unexpected(&format!("the end of the {kw} line")));
        }
        if depth + 1 > MAX_DEPTH {
            // One error for the whole block: skip it, with every block inside, to its END
            // (reporting each deeper opener and each END left over would be thousands of
            // errors for one mistake).
            self.skip_block();
            return Err(Diagnostic::error(keyword, format!("blocks nested more than {MAX_DEPTH} deep"))
                .with_hint("move the inner loops' work into fewer levels; the whole block was skipped"));
        }
        Ok(self.block(Some((kw, keyword)), depth + 1))
    }

    /// Skips statements up to the END that closes the block just opened (counting the
    /// LOOP/FOR and END that start statements), leaving that END's line end for `sync`.
    fn skip_block(&mut self) {
        let mut open = 1usize;
        let mut line_start = true;
        while let Some(t) = self.peek_tok() {
            if *t == Tok::End {
                line_start = true;
                self.bump();
                continue;
            }
            if line_start {
                if is_kw(t, "LOOP") || is_kw(t, "FOR") {
                    open += 1;
                } else if is_kw(t, "END") {
                    open -= 1;
                    if open == 0 {
                        self.bump();
                        return;
                    }
                }
            }
            line_start = false;
            self.bump();
        }
    }

    fn motion_opts(&mut self) -> PResult<MotionOpts> {
        let mut opts = MotionOpts::default();
        loop {
            if self.at_kw("BLEND") {
                let at = self.bump().expect("peeked").span;
                if opts.blend.is_some() {
                    return Err(Diagnostic::error(at, "BLEND given twice"));
                }
                opts.blend = Some(self.expr()?);
            } else if self.at_kw("IN") {
                let at = self.bump().expect("peeked").span;
                if opts.duration.is_some() {
                    return Err(Diagnostic::error(at, "IN given twice"));
                }
                opts.duration = Some(self.expr()?);
            } else if self.at_kw("AVOID") {
                let at = self.bump().expect("peeked").span;
                if opts.avoid.is_some() {
                    return Err(Diagnostic::error(at, "AVOID given twice"));
                }
                opts.avoid = Some(at);
            } else {
                return Ok(opts);
            }
        }
    }

    fn target(&mut self) -> PResult<Target> {
        let start = self.here().start;
        if self.at_kw("JOINT") || self.at_kw("CART") {
            let joint = self.at_kw("JOINT");
            self.bump();
            self.expect(Tok::LParen, "`(`")?;
            let mut items = Vec::new();
            if self.peek_tok() != Some(&Tok::RParen) {
                loop {
                    items.push(self.expr()?);
                    if self.peek_tok() == Some(&Tok::Comma) {
                        self.bump();
                        continue;
                    }
                    break;
                }
            }
            self.expect(Tok::RParen, "`,` or `)`")?;
            let span = start..self.prev_end();
            return Ok(if joint { Target::Joint(items, span) } else { Target::Cart(items, span) });
        }
        match self.peek_tok() {
            Some(Tok::Ident(_)) => Ok(Target::Named(self.name("a position")?)),
            _ => Err(self.unexpected("a position (a name, JOINT(...) or CART(...))")),
        }
    }

    /// Counts one operator at `at`; an error past [`MAX_OPERATORS`].
    fn operator(&mut self, at: Span) -> PResult<()> {
        self.operators += 1;
        if self.operators > MAX_OPERATORS {
            return Err(Diagnostic::error(at, format!("more than {MAX_OPERATORS} operators in one statement"))
                .with_hint("split the computation, or write the value out"));
        }
        Ok(())
    }

    fn expr(&mut self) -> PResult<Expr> {
        let mut lhs = self.term()?;
        loop {
            let op = match self.peek_tok() {
                Some(Tok::Plus) => BinOp::Add,
                Some(Tok::Minus) => BinOp::Sub,
                _ => return Ok(lhs),
            };
            let at = self.bump().expect("peeked").span;
            self.operator(at)?;
            let rhs = self.term()?;
            let span = lhs.span().start..rhs.span().end;
            lhs = Expr::Bin { op, lhs: Box::new(lhs), rhs: Box::new(rhs), span };
        }
    }

    fn term(&mut self) -> PResult<Expr> {
        let mut lhs = self.unary(0)?;
        loop {
            let op = match self.peek_tok() {
                Some(Tok::Star) => BinOp::Mul,
                Some(Tok::Slash) => BinOp::Div,
                _ => return Ok(lhs),
            };
            let at = self.bump().expect("peeked").span;
            self.operator(at)?;
            let rhs = self.unary(0)?;
            let span = lhs.span().start..rhs.span().end;
            lhs = Expr::Bin { op, lhs: Box::new(lhs), rhs: Box::new(rhs), span };
        }
    }

    fn unary(&mut self, depth: usize) -> PResult<Expr> {
        if depth > MAX_DEPTH {
            return Err(Diagnostic::error(self.here(), "expression nested too deeply"));
        }
        match self.peek_tok() {
            Some(Tok::Minus) => {
                let at = self.bump().expect("peeked").span;
                self.operator(at.clone())?;
                let start = at.start;
                let e = self.unary(depth + 1)?;
                let span = start..e.span().end;
                Ok(Expr::Neg(Box::new(e), span))
            }
            Some(Tok::Plus) => {
                self.bump();
                self.unary(depth + 1)
            }
            Some(Tok::Number(v, u)) => {
                let (value, unit) = (*v, u.clone());
                let span = self.bump().expect("peeked").span;
                Ok(Expr::Num { value, unit, span })
            }
            Some(Tok::Ident(_)) => Ok(Expr::Var(self.name("a value")?)),
            Some(Tok::LParen) => {
                let open = self.bump().expect("peeked").span;
                if self.parens >= MAX_DEPTH {
                    return Err(Diagnostic::error(open, "expression nested too deeply"));
                }
                self.parens += 1;
                let e = self.expr();
                self.parens -= 1;
                let e = e?;
                self.expect(Tok::RParen, "`)`")?;
                Ok(e)
            }
            _ => Err(self.unexpected("a value (a number with its unit, or a FOR counter)")),
        }
    }
}

/// The keyword closest to a misspelt one (edit distance ≤ 2).
fn suggestion(word: &str) -> Option<&'static str> {
    let w = word.to_ascii_uppercase();
    KEYWORDS.iter().map(|k| (edit_distance(&w, k), *k)).filter(|(d, _)| *d <= 2).min().map(|(_, k)| k)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb)).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}
