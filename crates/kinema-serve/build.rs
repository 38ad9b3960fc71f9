//! Bundles the viewer's page (`web/src/*.js` with three.js from npm) into
//! `$OUT_DIR/viewer.js`, which the server embeds with `include_str!`.
//!
//! The npm packages are installed by `npm ci` from `web/package-lock.json`
//! into `$OUT_DIR/web/node_modules`, once per target directory and again only
//! when the lockfile changes; esbuild then bundles the sources. Nothing from
//! npm is kept in the repository.

use std::path::{Path, PathBuf};
use std::process::Command;

const HOW_TO_INSTALL: &str = "kinema-serve bundles its web page (three.js, from npm) when it is built, which needs \
     Node.js 18 or later and npm: install them from https://nodejs.org or with your package manager \
     (Debian/Ubuntu: `apt-get install nodejs npm`; macOS: `brew install node`), then build again";

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let web = manifest.join("web");
    for watched in ["package.json", "package-lock.json", "src"] {
        println!("cargo:rerun-if-changed={}", web.join(watched).display());
    }
    let work = out.join("web");
    std::fs::create_dir_all(&work).unwrap_or_else(|e| fail(&format!("cannot create {}: {e}", work.display())));
    install(&web, &work);
    bundle(&web, &work, &out.join("viewer.js"));
}

/// `npm ci` in `work` when its installed lockfile differs from `web`'s.
fn install(web: &Path, work: &Path) {
    let lock = read(&web.join("package-lock.json"));
    let stamp = work.join("installed-package-lock.json");
    if std::fs::read_to_string(&stamp).is_ok_and(|s| s == lock) && work.join("node_modules").is_dir() {
        return;
    }
    for file in ["package.json", "package-lock.json"] {
        std::fs::copy(web.join(file), work.join(file))
            .unwrap_or_else(|e| fail(&format!("cannot copy web/{file} to {}: {e}", work.display())));
    }
    let hint = "npm needs the registry (https://registry.npmjs.org) the first time, or a cache holding the packages \
                of web/package-lock.json";
    run(npm().args(["ci", "--no-audit", "--no-fund", "--loglevel=error"]).current_dir(work), "npm ci", hint);
    std::fs::write(&stamp, lock).unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", stamp.display())));
}

/// esbuild: `web/src/main.js` and what it imports, one minified script.
fn bundle(web: &Path, work: &Path, to: &Path) {
    // npm's launcher: a native binary or a script, depending on esbuild's install step.
    let esbuild = work.join("node_modules").join(".bin").join(if cfg!(windows) { "esbuild.cmd" } else { "esbuild" });
    let mut command = Command::new(esbuild);
    command
        .arg(web.join("src").join("main.js"))
        .args(["--bundle", "--format=iife", "--target=es2020", "--minify", "--log-level=warning"])
        .arg(format!("--outfile={}", to.display()))
        // The packages are in the target directory, not beside the sources.
        .env("NODE_PATH", work.join("node_modules"));
    run(&mut command, "esbuild (bundling web/src/main.js)", "the sources in web/src do not bundle");
}

fn npm() -> Command {
    // On Windows npm is a batch file, which `Command` does not find by its bare name.
    Command::new(if cfg!(windows) { "npm.cmd" } else { "npm" })
}

fn run(command: &mut Command, what: &str, hint: &str) {
    match command.status() {
        Ok(status) if status.success() => {}
        Ok(status) => fail(&format!("{what} failed ({status}); its output is above: {hint}")),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            fail(&format!("{what}: not found ({e}). {HOW_TO_INSTALL}"))
        }
        Err(e) => fail(&format!("{what} could not be started: {e}. {HOW_TO_INSTALL}")),
    }
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", path.display())))
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    panic!("{message}");
}
