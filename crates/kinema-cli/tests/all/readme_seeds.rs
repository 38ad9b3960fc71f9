//! docs/seeds.md is checked against what kinema prints (issue 34), with the
//! documents' machinery of `readme.rs` and rules for its tables:
//!
//! - In every table row, each backticked span that starts with `kinema ` is a
//!   command, and runs, unless it contains `…` or `<` (then it names or
//!   abbreviates a command written out elsewhere). It must exit with 0, or with
//!   N when the span is followed by `(exit N)`. `\|` is a `|`, and a word with
//!   `|` lists alternatives, as in the documents.
//! - In the columns [`SEEDS_CHECKED_COLUMNS`] (`kinema`, `correction / note`),
//!   every other backticked span is a quote of what the row's commands print
//!   (stdout and stderr of all of them together), and must appear there
//!   verbatim, runs of white space (line ends included) counting as one space;
//!   `…` inside a quote stands for text left out, the pieces appearing in
//!   order. Not quotes: options (`--…`), Rust paths (`::`) and file names.
//! - A row that quotes output must run a command. Rows run in document order in
//!   one temporary directory (a row may read a file an earlier row wrote),
//!   with the documents' [`fixtures`] and [`seeds_fixtures`]; a command is skipped
//!   only if [`SEEDS_SKIP`] lists it with the reason, and an entry that matches
//!   no command is an error.
//! - The Summary's counts of rows, and of rows that quote output, per seed,
//!   are those of the tables ([`seeds_summary`]).

use std::path::Path;
use std::time::Instant;

use crate::common;
use crate::readme::{expand, fixtures, repo, words, write, TIME_LIMIT};

/// Commands of docs/seeds.md not run: (the command as written, or its beginning; why).
const SEEDS_SKIP: &[(&str, &str)] =
    &[("kinema serve", "a server: it runs until stopped (the documents' test starts one and stops it)")];

/// Columns of docs/seeds.md's tables whose backticked spans quote output.
const SEEDS_CHECKED_COLUMNS: &[&str] = &["kinema", "correction / note"];

/// One command of a docs/seeds.md row.
#[derive(Debug, Clone, PartialEq)]
struct SeedCommand {
    /// As written (`\|` read as `|`).
    text: String,
    /// Its arguments after `kinema`.
    args: Vec<String>,
    /// The exit code it must end with.
    exit: i32,
}

/// One table row of docs/seeds.md.
#[derive(Debug)]
struct SeedRow {
    /// Line in the document (1-based).
    line: usize,
    /// The seed of its section (`## Seed 000 …` gives `000`).
    seed: String,
    /// The first cell (the paper's item).
    item: String,
    /// The commands to run.
    commands: Vec<SeedCommand>,
    /// What the row quotes from the commands' output.
    quotes: Vec<String>,
}

/// A table row's cells: split on `|` not preceded by `\` (as GitHub does, code spans
/// included), with `\|` read as `|`.
fn table_cells(line: &str) -> Vec<String> {
    let mut cells = vec![String::new()];
    let mut chars = line.trim().chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                chars.next();
                cells.last_mut().unwrap().push('|');
            }
            '|' => cells.push(String::new()),
            c => cells.last_mut().unwrap().push(c),
        }
    }
    // The empty strings before the first and after the last `|`.
    cells.remove(0);
    cells.pop();
    cells.into_iter().map(|c| c.trim().to_string()).collect()
}

/// The backticked spans of a cell, each with the text that follows it up to the next span.
fn code_spans(cell: &str, line: usize) -> Vec<(String, String)> {
    let parts: Vec<&str> = cell.split('`').collect();
    assert!(parts.len() % 2 == 1, "docs/seeds.md:{line}: unbalanced backticks in `{cell}`");
    (1..parts.len()).step_by(2).map(|k| (parts[k].to_string(), parts[k + 1].to_string())).collect()
}

/// Whether a backticked span in a checked column names something rather than quoting output.
fn is_name(span: &str) -> bool {
    let file = !span.contains(char::is_whitespace)
        && (span.contains('/')
            || [".rs", ".md", ".png", ".svg", ".csv", ".toml", ".prg"].iter().any(|e| span.ends_with(e)));
    span.starts_with("--") || span.contains("::") || file
}

/// Every table row of docs/seeds.md with its commands and quotes.
fn seed_rows(doc: &str) -> Vec<SeedRow> {
    let lines: Vec<&str> = doc.lines().collect();
    let mut rows = Vec::new();
    let mut header: Vec<String> = Vec::new();
    let mut seed = String::new();
    for (k, line) in lines.iter().enumerate() {
        if let Some(title) = line.strip_prefix("## Seed ") {
            seed = title.chars().take_while(char::is_ascii_digit).collect();
        }
        if !line.trim_start().starts_with('|') {
            header.clear();
            continue;
        }
        let cells = table_cells(line);
        if lines
            .get(k + 1)
            .is_some_and(|next| next.trim_start().starts_with("|--") || next.trim_start().starts_with("| --"))
        {
            header = cells;
            continue;
        }
        if cells.iter().all(|c| c.chars().all(|c| c == '-' || c == ':')) {
            continue;
        }
        assert_eq!(
            cells.len(),
            header.len(),
            "docs/seeds.md:{}: {} cells under a header of {}",
            k + 1,
            cells.len(),
            header.len()
        );
        let mut row = SeedRow {
            line: k + 1,
            seed: seed.clone(),
            item: cells[0].clone(),
            commands: Vec::new(),
            quotes: Vec::new(),
        };
        for (cell, name) in cells.iter().zip(&header) {
            let checked = SEEDS_CHECKED_COLUMNS.contains(&name.as_str());
            for (span, after) in code_spans(cell, k + 1) {
                if let Some(command) = span.strip_prefix("kinema ") {
                    if span.contains('…') || span.contains('<') {
                        continue;
                    }
                    let exit = after.trim_start().strip_prefix("(exit ").map_or(0, |rest| {
                        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
                        digits.parse().unwrap_or_else(|_| panic!("docs/seeds.md:{}: `(exit` without a number", k + 1))
                    });
                    row.commands.push(SeedCommand { text: span.clone(), args: words(command).0, exit });
                } else if checked && !is_name(&span) {
                    row.quotes.push(span);
                }
            }
        }
        rows.push(row);
    }
    rows
}

/// Whether `quote` appears in `printed`, white space runs counting as one space and
/// `…` standing for anything (the pieces in order).
fn quoted_in(quote: &str, printed: &str) -> bool {
    let printed = printed.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut rest = printed.as_str();
    for piece in quote.split('…') {
        let piece = piece.split_whitespace().collect::<Vec<_>>().join(" ");
        if piece.is_empty() {
            continue;
        }
        match rest.find(&piece) {
            Some(at) => rest = &rest[at + piece.len()..],
            None => return false,
        }
    }
    true
}

/// Files docs/seeds.md's commands read that neither [`fixtures`] nor an earlier row make.
fn seeds_fixtures(dir: &Path) {
    // Seed 004 eq. 20: the iiwa with d7 = 0, as the row's `sed` makes it.
    let iiwa = std::fs::read_to_string(repo().join("robots/lbr-iiwa-14-r820.toml")).unwrap();
    assert!(iiwa.contains("\nd = 126\n"), "the iiwa's A7 has d = 126");
    write(dir, "iiwa-wrist.toml", &iiwa.replace("\nd = 126\n", "\nd = 0\n"));
    // Seed 001 Tabla 2: ROMMEL with the printed values (d1 = 0.215, l1x = 0.5 m), and with the
    // other fix that reproduces eq. 8 (d1 = 0.215, l2 = 0.270 m instead of d1 = 0.270, l2 = 0.215).
    let rommel = std::fs::read_to_string(repo().join("robots/rommel.toml")).unwrap();
    let replace = |text: &str, from: &str, to: &str| {
        assert_eq!(text.matches(from).count(), 1, "robots/rommel.toml has one `{}`", from.trim());
        text.replace(from, to)
    };
    let printed = replace(&rommel, "\nd = 0.270\n", "\nd = 0.215\n");
    write(dir, "rommel-tabla2.toml", &replace(&printed, "\na = 0.05\n", "\na = 0.5\n"));
    write(dir, "rommel-l2.toml", &replace(&printed, "\na = 0.215\n", "\na = 0.270\n"));
    // Seed 000 Fig. 5: the line along y the row gives (pitch in degrees).
    write(dir, "line_y.csv", "x,y,z,pitch\n0.35,-0.10,0.30,60\n0.35,0.10,0.30,60\n");
}

/// The Summary's lines that count the rows of each seed, and those that quote output.
fn seeds_summary(rows: &[SeedRow]) -> [String; 2] {
    let count = |quoting: bool| {
        let seeds = ["000", "001", "003", "004"];
        let per: Vec<usize> = seeds
            .iter()
            .map(|s| rows.iter().filter(|r| r.seed == *s && (!quoting || !r.quotes.is_empty())).count())
            .collect();
        let list: Vec<String> = seeds.iter().zip(&per).map(|(s, n)| format!("seed {s}: {n}")).collect();
        (list.join(", "), per.iter().sum::<usize>())
    };
    let (all, total) = count(false);
    let (quoting, quoting_total) = count(true);
    [
        format!("* Rows: {all} — {total} in all."),
        format!("* Rows that quote kinema's output, each quote checked against a run: {quoting} — {quoting_total}."),
    ]
}

#[test]
fn every_seeds_row_matches_what_kinema_prints() {
    let doc = std::fs::read_to_string(repo().join("docs/seeds.md")).expect("docs/seeds.md");
    let rows = seed_rows(&doc);
    let commands = rows.iter().map(|r| r.commands.len()).sum::<usize>();
    assert!(
        rows.len() > 100 && commands > 100,
        "{} rows, {commands} commands in docs/seeds.md: is the parser broken?",
        rows.len()
    );
    for (skip, _) in SEEDS_SKIP {
        assert!(
            rows.iter().flat_map(|r| &r.commands).any(|c| c.text.starts_with(skip)),
            "SEEDS_SKIP names `{skip}`, which is not in docs/seeds.md"
        );
    }
    let mut failures = Vec::new();
    for line in seeds_summary(&rows) {
        if !doc.lines().any(|l| l == line) {
            failures.push(format!("docs/seeds.md: the Summary does not say\n{line}"));
        }
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    fixtures(dir.path());
    seeds_fixtures(dir.path());
    let start = Instant::now();
    let mut runs = 0;
    for row in &rows {
        let what = format!("docs/seeds.md:{} ({})", row.line, row.item);
        let mut printed = String::new();
        let mut ran = false;
        for c in &row.commands {
            if let Some((_, why)) = SEEDS_SKIP.iter().find(|(s, _)| c.text.starts_with(s)) {
                eprintln!("skipped {what}: {} ({why})", c.text);
                continue;
            }
            for args in expand(&c.args) {
                let t = Instant::now();
                let r = common::kinema_in(dir.path(), &args, TIME_LIMIT);
                runs += 1;
                ran = true;
                eprintln!("{:6.2} s  {what}: kinema {}", t.elapsed().as_secs_f64(), args.join(" "));
                if r.code != Some(c.exit) {
                    failures.push(format!(
                        "{what}: kinema {}\n  exit code {:?}, the row expects {}\n  stderr: {}",
                        args.join(" "),
                        r.code,
                        c.exit,
                        r.stderr.trim()
                    ));
                }
                printed += &r.stdout;
                printed += "\n";
                printed += &r.stderr;
                printed += "\n";
            }
        }
        if !row.quotes.is_empty() && !ran {
            failures.push(format!("{what}: quotes {:?} but runs no command", row.quotes));
        }
        let missing: Vec<&String> = row.quotes.iter().filter(|q| !quoted_in(q, &printed)).collect();
        if ran && !missing.is_empty() {
            failures.push(format!(
                "{what}: not printed by its commands: {missing:#?}\n  they printed:\n{}",
                printed.trim()
            ));
        }
    }
    eprintln!("{} docs/seeds.md rows, {runs} runs in {:.1} s", rows.len(), start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} docs/seeds.md row(s) failed:\n\n{}", failures.len(), failures.join("\n\n"));
}

#[test]
fn the_seeds_parser_follows_the_rules() {
    let doc = "| item | reproduced by | kinema | correction / note |\n\
        |---|---|---|---|\n\
        | eq. 1 | `kinema fk --robot ur5 --q home`; `kinema fk …` | `x = 0.1` … `1 A1` | `seeds::x`, `--deg`, `ik/ur.rs`, `q \\|Δq\\|` |\n\
        | eq. 2 | `kinema ik --robot a\\|b --q 1` (exit 2) | — | `kinema manip --q <q>` |\n\
        \n\
        | a | b |\n\
        | --- | --- |\n\
        | `x` | `kinema robots` |\n";
    let rows = seed_rows(doc);
    assert_eq!(rows.len(), 3, "{rows:#?}");
    assert_eq!((rows[0].line, rows[0].item.as_str()), (3, "eq. 1"));
    assert_eq!(
        rows[0].commands,
        [SeedCommand {
            text: "kinema fk --robot ur5 --q home".into(),
            args: words("fk --robot ur5 --q home").0,
            exit: 0
        }]
    );
    assert_eq!(rows[0].quotes, ["x = 0.1", "1 A1", "q |Δq|"]);
    assert_eq!((rows[1].commands[0].exit, expand(&rows[1].commands[0].args).len()), (2, 2));
    assert!(rows[1].quotes.is_empty());
    assert_eq!((rows[2].commands.len(), rows[2].quotes.len()), (1, 0));
    // A quote is found with its white space and its `…`; one wrong digit is not.
    let printed = "max |Δq| 3.597e-12,\n  mean 2.990e-15, recovered 100.00 %\n";
    assert!(quoted_in("max |Δq| 3.597e-12, mean 2.990e-15", printed));
    assert!(quoted_in("max |Δq| … recovered 100.00 %", printed));
    assert!(!quoted_in("max |Δq| 3.598e-12", printed));
    assert!(!quoted_in("recovered … max", printed));
}
