//! Every `kinema` command in the code blocks of README.md and of docs/*.md runs
//! (issues 25 and 36), docs/seeds.md's rows print what they quote (issue 34), and
//! every relative link of the Markdown files resolves.
//!
//! The rules, so that an example added to a document is run without touching
//! this file. They apply to README.md and to every docs/*.md but docs/seeds.md
//! ([`documents`]), each document on its own:
//!
//! - In a block fenced as `sh` (or `bash`, `shell`), every line that starts
//!   with `kinema` is a command. A line ending in `\` continues on the next
//!   one; `#` at the start of a word begins a comment. Any other line must
//!   start with one of [`OTHER_PROGRAMS`] (`cargo`, `bash`: run by `.ci/run`;
//!   `curl`: needs a running server).
//! - A word with `|` lists alternatives (`--kind joint|cartesian`): the
//!   command runs once per alternative.
//! - A command ending in `&` starts in the background (the Scorbot simulator):
//!   the block's next commands wait until its `--tcp` address accepts
//!   connections, it must still be running when the block ends, and is then
//!   stopped.
//! - A command must exit with 0, or with N where its comment says
//!   `exit code N`. A command with `--json` must print JSON.
//! - In a block fenced as `text`, a line `$ kinema …` is a transcript: the
//!   lines after it, up to the next `$` line, are what the command prints
//!   (stdout and stderr), and it exits with 1 if that begins with `error:`,
//!   else with 0.
//! - A document's commands run in its order, in a temporary directory of its
//!   own (a command may read what an earlier one of the same document wrote,
//!   e.g. `lin.csv`: keep such commands together), each within
//!   [`TIME_LIMIT`]. Files the documents read but never write are made by
//!   [`fixtures`] in every directory; the address `127.0.0.1:7777` becomes a
//!   free port.
//! - A command is skipped only if it is listed in [`SKIP`] with the reason;
//!   an entry that matches no documented command is an error.
//!
//! docs/seeds.md is checked by `readme_seeds.rs` with rules of its own.
//!
//! Links ([`every_relative_link_resolves`]): in README.md, ARCHITECTURE.md,
//! CHANGELOG.md, docs/*.md, benchmarks/README.md and crates/*/README.md, every
//! Markdown link `[text](target)` whose target is not a URL or an anchor of the
//! same file names a file or folder that exists (relative to the linking file).
//!
//! The Python code blocks of README.md and docs/*.md are run by
//! crates/kinema-py/tests/test_readme.py, the Rust examples in
//! crates/kinema/examples/ by `.ci/run`.

use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use kinema::{Robot, RpyConvention};
use kinema_scorbot::calib::tool_position;
use kinema_scorbot::encoder::Constants;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;

/// The longest a single command may take.
pub(crate) const TIME_LIMIT: Duration = Duration::from_secs(30);

/// Commands not run: (the command as a document writes it, continuations joined
/// and the comment removed, or its beginning; why).
const SKIP: &[(&str, &str)] = &[];

/// Programs other than `kinema` that the documents' `sh` blocks may call (not run
/// here: `cargo` and `bash` by `.ci/run`, `pip` by crates/kinema-py/ci.sh; `curl`
/// needs a running server).
const OTHER_PROGRAMS: &[&str] = &["cargo", "bash", "curl", "pip"];

/// The documents' TCP address of the Scorbot simulator, replaced by a free port.
const SIM_ADDRESS: &str = "127.0.0.1:7777";

pub(crate) fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The documents whose commands run, in order: README.md, then docs/*.md by name but
/// docs/seeds.md (which has its own rules), as paths relative to the repository.
fn documents() -> Vec<String> {
    let mut docs: Vec<String> = std::fs::read_dir(repo().join("docs"))
        .expect("docs/")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".md") && name != "seeds.md")
        .map(|name| format!("docs/{name}"))
        .collect();
    docs.sort();
    docs.insert(0, "README.md".to_string());
    docs
}

/// One command found in a document.
#[derive(Debug, Clone)]
struct Example {
    /// Line of the document where it starts (1-based).
    line: usize,
    /// The command as written (continuations joined, comment removed).
    text: String,
    /// Its arguments after `kinema`.
    args: Vec<String>,
    /// The exit code it must end with.
    exit: i32,
    /// Started in the background (`&`).
    background: bool,
    /// A transcript's expected output.
    output: Option<Vec<String>>,
    /// Index of the code block it is in.
    block: usize,
}

/// Splits a command line into words (single and double quotes group) and its comment.
pub(crate) fn words(line: &str) -> (Vec<String>, String) {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '"' | '\'') => {
                quote = Some(c);
                in_word = true;
            }
            (None, '#') if !in_word => return (out, line[i + 1..].trim().to_string()),
            (None, c) if c.is_whitespace() => {
                if in_word {
                    out.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            (None, c) => {
                word.push(c);
                in_word = true;
            }
        }
    }
    assert!(quote.is_none(), "unclosed quote in the command `{line}`");
    if in_word {
        out.push(word);
    }
    (out, String::new())
}

/// The exit code a comment announces (`exit code N`), else 0.
fn expected_exit(comment: &str) -> i32 {
    comment
        .split("exit code ")
        .nth(1)
        .map(|rest| {
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            digits.parse().unwrap_or_else(|_| panic!("`exit code` without a number in `# {comment}`"))
        })
        .unwrap_or(0)
}

/// Every `kinema` command of a document's `sh` blocks and `text` transcripts (`name`
/// is the document's, for messages).
fn examples(name: &str, readme: &str) -> Vec<Example> {
    let mut found = Vec::new();
    let mut fence: Option<String> = None;
    let mut block = 0;
    let lines: Vec<&str> = readme.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let start = i + 1;
        i += 1;
        if let Some(info) = line.trim_start().strip_prefix("```") {
            fence = match fence {
                None => {
                    block += 1;
                    Some(info.trim().to_string())
                }
                Some(_) => None,
            };
            continue;
        }
        match fence.as_deref() {
            Some("sh" | "bash" | "shell") => {
                let mut text = line.to_string();
                while text.trim_end().ends_with('\\') && i < lines.len() {
                    text = format!("{} {}", text.trim_end().trim_end_matches('\\'), lines[i].trim());
                    i += 1;
                }
                let (mut args, comment) = words(&text);
                if args.is_empty() {
                    continue;
                }
                if args[0] != "kinema" {
                    assert!(
                        OTHER_PROGRAMS.contains(&args[0].as_str()),
                        "{name}:{start}: `{}` is neither a kinema command nor one of {OTHER_PROGRAMS:?}",
                        args[0]
                    );
                    continue;
                }
                let background = args.last().is_some_and(|a| a == "&");
                if background {
                    args.pop();
                }
                let text = args.join(" ");
                args.remove(0);
                found.push(Example {
                    line: start,
                    text,
                    args,
                    exit: expected_exit(&comment),
                    background,
                    output: None,
                    block,
                });
            }
            Some("text") => {
                let Some(command) = line.strip_prefix("$ kinema ") else { continue };
                let mut output = Vec::new();
                while i < lines.len() && !lines[i].starts_with("$ ") && !lines[i].trim_start().starts_with("```") {
                    output.push(lines[i].trim_end().to_string());
                    i += 1;
                }
                let (args, _) = words(command);
                let exit = if output.first().is_some_and(|l| l.starts_with("error:")) { 1 } else { 0 };
                found.push(Example {
                    line: start,
                    text: format!("kinema {command}"),
                    args,
                    exit,
                    background: false,
                    output: Some(output),
                    block,
                });
            }
            _ => {}
        }
    }
    assert!(fence.is_none(), "{name} ends inside a code block");
    found
}

/// The commands an example stands for: one per alternative of a word with `|`.
pub(crate) fn expand(args: &[String]) -> Vec<Vec<String>> {
    let mut all = vec![Vec::new()];
    for a in args {
        let choices: Vec<&str> = a.split('|').collect();
        all = all
            .iter()
            .flat_map(|prefix| {
                choices.iter().map(move |c| {
                    let mut v: Vec<String> = prefix.clone();
                    v.push(c.to_string());
                    v
                })
            })
            .collect();
    }
    all
}

pub(crate) fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap_or_else(|e| panic!("write fixture {name}: {e}"));
}

/// Writes the files the documents' commands read but none of them writes.
pub(crate) fn fixtures(dir: &Path) {
    let repo = repo();
    let copy = |from: PathBuf, to: &str| {
        std::fs::copy(&from, dir.join(to)).unwrap_or_else(|e| panic!("copy {}: {e}", from.display()));
    };
    // `fk --robot my_arm.urdf --tip tool0`: any URDF arm with a link tool0.
    copy(repo.join("crates/kinema/tests/data/ur5.urdf"), "my_arm.urdf");
    // The robot programs, cells, scenes and tasks, at the paths the documents give.
    for folder in ["examples/programs", "examples/cells", "examples/scenes", "examples/tasks"] {
        std::fs::create_dir_all(dir.join(folder)).unwrap();
        for entry in std::fs::read_dir(repo.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            copy(path.clone(), &format!("{folder}/{}", path.file_name().unwrap().to_string_lossy()));
        }
    }
    // `fk --robot broken.toml`: the Scorbot's file without the shoulder's link twist.
    let scorbot = std::fs::read_to_string(repo.join("robots/scorbot-er-v-plus.toml")).unwrap();
    let shoulder = scorbot.find("name = \"shoulder\"").expect("the Scorbot has a shoulder");
    let alpha = shoulder + scorbot[shoulder..].find("alpha = 0\n").expect("the shoulder's alpha");
    write(dir, "broken.toml", &format!("{}{}", &scorbot[..alpha], &scorbot[alpha + "alpha = 0\n".len()..]));

    let mut rng = ChaCha8Rng::seed_from_u64(25);
    // `fk --robot puma560 --input q.csv`: configurations, with a header and a comment.
    let puma = Robot::builtin("puma560").unwrap();
    let mut q_csv = String::from("q1,q2,q3,q4,q5,q6\n# random configurations within the limits\n");
    for _ in 0..20 {
        q_csv += &join(&puma.random_q(&mut rng));
        q_csv += "\n";
    }
    write(dir, "q.csv", &q_csv);
    // `ik --robot ur5 --input targets.csv`: reachable targets in the three forms (16, 6, 3 numbers).
    let ur5 = Robot::builtin("ur5").unwrap();
    let mut targets = String::new();
    for k in 0..12 {
        let pose = ur5.fk(&ur5.random_q(&mut rng)).unwrap().world_from_tool;
        let numbers: Vec<f64> = match k % 3 {
            0 => pose.to_matrix().transpose().iter().copied().collect(),
            1 => pose.pos.iter().copied().chain(pose.rpy(RpyConvention::Zyx)).collect(),
            _ => pose.pos.iter().copied().collect(),
        };
        targets += &join(&numbers);
        targets += "\n";
    }
    write(dir, "targets.csv", &targets);

    // The Scorbot: seed 000 Fig. 6's square (10 cm in the xz plane, pitch 60°: with
    // pitch 0 the elbow leaves its limits there), two "measured" runs a millimetre or
    // two off it, and calibration samples simulated like kinema-scorbot's example 01.
    let corners = [(0.30, 0.25), (0.40, 0.25), (0.40, 0.35), (0.30, 0.35), (0.30, 0.25)];
    let pitch = 60f64.to_radians();
    let square: String =
        corners.iter().map(|(x, z)| format!("{x},0,{z},{pitch}\n")).fold("x,y,z,pitch\n".to_string(), |s, l| s + &l);
    write(dir, "square.csv", &square);
    for run in 1..=2 {
        let mut text = String::from("x,y,z\n");
        for w in corners.windows(2) {
            for s in 0..10 {
                let f = s as f64 / 10.0;
                let (x, z) = (w[0].0 + f * (w[1].0 - w[0].0), w[0].1 + f * (w[1].1 - w[0].1));
                text += &format!("{},{},{}\n", x + 0.001 * run as f64, -0.0005 * run as f64, z + 0.0005);
            }
        }
        write(dir, &format!("run{run}.csv"), &text);
    }
    let scorbot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let truth = Constants::named("calibrated").unwrap();
    let mut samples = String::from("c1,c2,c3,c4,c5,x,y,z\n");
    for _ in 0..150 {
        let counts = truth.counts_rounded(&scorbot.random_q(&mut rng)).unwrap().map(|c| c as f64);
        let p = tool_position(&scorbot, &truth, &counts).unwrap();
        let mut noise = || 0.001 * (rng.random_range(-1.0..1.0) + rng.random_range(-1.0..1.0));
        let p = [p.x + noise(), p.y + noise(), p.z + noise()];
        samples += &format!("{},{}\n", join(&counts), join(&p));
    }
    write(dir, "samples.csv", &samples);
}

fn join(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:.9}")).collect::<Vec<_>>().join(",")
}

fn free_address() -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a free port");
    listener.local_addr().unwrap().to_string()
}

/// Starts a background command; waits until its `--tcp` address accepts connections.
fn start_background(dir: &Path, args: &[String], what: &str) -> Child {
    let mut child = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("kinema starts");
    if let Some(addr) = args.iter().position(|a| a == "--tcp").and_then(|k| args.get(k + 1)) {
        let addr: SocketAddr = addr.parse().expect("a --tcp address");
        let start = Instant::now();
        while TcpStream::connect_timeout(&addr, Duration::from_millis(200)).is_err() {
            if let Some(status) = child.try_wait().unwrap() {
                panic!("{what}: ended ({status}) before listening on {addr}");
            }
            assert!(start.elapsed() < TIME_LIMIT, "{what}: not listening on {addr} after {TIME_LIMIT:?}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    child
}

fn stop_background(background: &mut Vec<(Child, String)>, failures: &mut Vec<String>) {
    for (mut child, what) in background.drain(..) {
        if let Some(status) = child.try_wait().unwrap() {
            failures.push(format!("{what}\n  ended ({status}) before the commands that need it were done"));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
}

#[test]
fn every_documented_command_runs() {
    let docs: Vec<(String, Vec<Example>)> = documents()
        .into_iter()
        .map(|name| {
            let text = std::fs::read_to_string(repo().join(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
            let found = examples(&name, &text);
            (name, found)
        })
        .collect();
    let total: usize = docs.iter().map(|(_, found)| found.len()).sum();
    assert!(total > 50, "only {total} kinema commands found in {:?}: is the parser broken?", documents());
    assert!(docs[0].1.len() >= 5, "only {} kinema commands in README.md's tour", docs[0].1.len());
    for (skip, _) in SKIP {
        assert!(
            docs.iter().flat_map(|(_, found)| found).any(|e| e.text.starts_with(skip)),
            "SKIP names `{skip}`, which is in no document"
        );
    }
    let mut failures = Vec::new();
    let start = Instant::now();
    for (name, found) in &docs {
        run_document(name, found, &mut failures);
    }
    eprintln!("{total} documented commands in {:.1} s", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} documented example(s) failed:\n\n{}", failures.len(), failures.join("\n\n"));
}

/// Runs one document's commands in order, in a temporary directory of its own.
fn run_document(name: &str, found: &[Example], failures: &mut Vec<String>) {
    if found.is_empty() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    fixtures(dir.path());
    let sim = free_address();
    let mut background: Vec<(Child, String)> = Vec::new();
    let mut block = 0;
    let start = Instant::now();
    for e in found {
        if e.block != block {
            stop_background(&mut background, failures);
            block = e.block;
        }
        if let Some((_, why)) = SKIP.iter().find(|(s, _)| e.text.starts_with(s)) {
            eprintln!("skipped {name}:{}: {} ({why})", e.line, e.text);
            continue;
        }
        let args: Vec<String> = e.args.iter().map(|a| a.replace(SIM_ADDRESS, &sim)).collect();
        for args in expand(&args) {
            let what = format!("{name}:{}: kinema {}", e.line, args.join(" "));
            if e.background {
                background.push((start_background(dir.path(), &args, &what), what));
                continue;
            }
            let t = Instant::now();
            let r = common::kinema_in(dir.path(), &args, TIME_LIMIT);
            eprintln!("{:6.2} s  {what}", t.elapsed().as_secs_f64());
            let mut problems = Vec::new();
            if r.code != Some(e.exit) {
                problems.push(format!("exit code {:?}, {name} expects {}", r.code, e.exit));
            }
            if let Some(expected) = &e.output {
                let printed: Vec<&str> = r.stdout.lines().chain(r.stderr.lines()).map(str::trim_end).collect();
                if printed != *expected {
                    problems.push(format!("printed {printed:#?}\n  {name} shows {expected:#?}"));
                }
            }
            if args.iter().any(|a| a == "--json") && r.ok {
                if let Err(err) = serde_json::from_str::<serde_json::Value>(&r.stdout) {
                    problems.push(format!("--json printed no JSON ({err})"));
                }
            }
            if !problems.is_empty() {
                failures.push(format!("{what}\n  {}\n  stderr: {}", problems.join("\n  "), r.stderr.trim()));
            }
        }
    }
    stop_background(&mut background, failures);
    eprintln!("{name}: {} commands in {:.1} s", found.len(), start.elapsed().as_secs_f64());
}

/// The Markdown files whose links are checked, relative to the repository.
fn linking_files() -> Vec<String> {
    let mut files: Vec<String> = ["README.md", "ARCHITECTURE.md", "CHANGELOG.md", "benchmarks/README.md"]
        .iter()
        .map(|f| f.to_string())
        .collect();
    for folder in ["docs", "crates"] {
        for entry in std::fs::read_dir(repo().join(folder)).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if folder == "docs" && name.ends_with(".md") {
                files.push(format!("docs/{name}"));
            } else if folder == "crates" && path.join("README.md").is_file() {
                files.push(format!("crates/{name}/README.md"));
            }
        }
    }
    files.sort();
    files
}

/// The targets of a Markdown text's inline links and images (`[text](target)`), outside code
/// blocks and code spans, each with its line.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let mut fence = false;
    for (k, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        // Code spans are not links: keep the text between them.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].split_whitespace().next().unwrap_or("").to_string();
            found.push((k + 1, target));
            rest = &after[end..];
        }
    }
    found
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in linking_files() {
        let text = std::fs::read_to_string(repo().join(&file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        let base = repo().join(&file).parent().unwrap().to_path_buf();
        for (line, target) in link_targets(&text) {
            if target.is_empty() || target.starts_with('#') || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let path = target.split('#').next().unwrap();
            checked += 1;
            if !base.join(path).exists() {
                broken.push(format!("{file}:{line}: `{target}`"));
            }
        }
    }
    assert!(checked > 20, "only {checked} relative links found: is the parser broken?");
    assert!(broken.is_empty(), "links to files that do not exist:\n{}", broken.join("\n"));
}

#[test]
fn the_link_parser_follows_the_rules() {
    let text = "see [a](docs/a.md#x) and ![b](b.png) `[c](not/a/link)`\n```\n[d](in/code)\n```\n[e](https://x.org)";
    let found: Vec<String> = link_targets(text).into_iter().map(|(_, t)| t).collect();
    assert_eq!(found, ["docs/a.md#x", "b.png", "https://x.org"]);
}

#[test]
fn the_parser_follows_the_rules() {
    let readme = "intro `kinema robots` in text is not run\n\
        ```sh\n\
        kinema fk --robot ur5 \\\n    --q home   # a comment with exit code 2\n\
        cargo test\n\
        kinema plot traj --kind a|b --out 'x y.png' &\n\
        ```\n\
        ```text\n\
        $ kinema fk --robot ur5 --q 1,2,3\n\
        error: wrong\n\
        $ kinema robots\n\
        ```\n\
        ```rust\n\
        kinema::Robot::builtin(\"ur5\");\n\
        ```\n";
    let found = examples("README.md", readme);
    assert_eq!(found.len(), 4, "{found:#?}");
    assert_eq!(found[0].args, ["fk", "--robot", "ur5", "--q", "home"]);
    assert_eq!((found[0].line, found[0].exit, found[0].background), (3, 2, false));
    assert_eq!(found[1].args, ["plot", "traj", "--kind", "a|b", "--out", "x y.png"]);
    assert!(found[1].background);
    assert_eq!(expand(&found[1].args).len(), 2);
    assert_eq!(expand(&found[1].args)[1][3], "b");
    assert_eq!((found[2].exit, found[2].output.as_deref()), (1, Some(&["error: wrong".to_string()][..])));
    assert_eq!((found[3].exit, found[3].output.as_ref().map(Vec::len)), (0, Some(0)));
}
