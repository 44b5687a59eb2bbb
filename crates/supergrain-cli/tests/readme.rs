//! The README's examples, run against the built binary as a user would type them, and the links
//! of the README and of `docs/*.md` checked.
//!
//! The convention for fenced blocks, which README.md follows (documented here, where it is
//! enforced):
//! - ` ```sh `: quick examples, run here verbatim by `sh`, in order, all in one temporary folder
//!   (holding a copy of `examples/scenes/`), with the built `supergrain` first on the `PATH`.
//!   Each line is one command, and each must succeed. In a block with `$ ` prompts, the lines
//!   after a `$ COMMAND` line (up to the next prompt or the block's end) are that command's
//!   exact standard output.
//! - ` ```bash `: examples too slow to run here (a long pour), or that need a window or the
//!   network (`view`, the web build). They are not run, but every `supergrain ...` command in
//!   them, also after `cargo run ... --`, is parsed by the binary with `--help` appended. clap
//!   checks each flag and value up to `--help`, so a flag that does not exist fails the test.
//!   The same check covers the ` ```sh ` and ` ```bash ` blocks of `docs/*.md`.
//! - ` ```toml `: the scene file of the README's reference, run for a few steps.
//! - ` ```text `, ` ```json `: output and formats, not checked. ` ```rust `: a doctest of the
//!   library (`crates/supergrain/src/lib.rs` includes the README).

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{stderr, stdout};

fn repo() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

/// A fenced code block: its info string, its lines and the line of its opening fence.
struct Block {
    lang: String,
    lines: Vec<String>,
    line: usize,
}

fn blocks(markdown: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (k, line) in markdown.lines().enumerate() {
        match (line.strip_prefix("```"), open.take()) {
            (Some(info), None) => {
                open = Some(Block {
                    lang: info.trim().to_string(),
                    lines: Vec::new(),
                    line: k + 1,
                })
            }
            (Some(_), Some(b)) => out.push(b),
            (None, Some(mut b)) => {
                b.lines.push(line.to_string());
                open = Some(b);
            }
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "a fenced block is not closed");
    out
}

/// A command of a ` ```sh ` block, and its expected output if the block is a transcript.
struct Example {
    command: String,
    output: Option<String>,
    line: usize,
}

fn examples(block: &Block) -> Vec<Example> {
    let transcript = block.lines.iter().any(|l| l.starts_with("$ "));
    let mut out: Vec<Example> = Vec::new();
    let mut pending = String::new();
    for (k, line) in block.lines.iter().enumerate() {
        let line_no = block.line + 1 + k;
        if transcript {
            match line.strip_prefix("$ ") {
                Some(command) => out.push(Example {
                    command: command.to_string(),
                    output: Some(String::new()),
                    line: line_no,
                }),
                None => {
                    let last = out.last_mut().unwrap_or_else(|| {
                        panic!("README line {line_no}: output before the first `$ ` prompt")
                    });
                    let expected = last.output.get_or_insert_with(String::new);
                    expected.push_str(line);
                    expected.push('\n');
                }
            }
            continue;
        }
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        match trimmed.strip_suffix('\\') {
            Some(part) => {
                pending.push_str(part);
                pending.push(' ');
            }
            None => {
                pending.push_str(trimmed);
                out.push(Example {
                    command: std::mem::take(&mut pending),
                    output: None,
                    line: line_no,
                });
            }
        }
    }
    out
}

/// The `supergrain` arguments of a line of a ` ```bash ` block, if it runs the binary: after
/// `supergrain` or after `cargo run ... --`, up to a `#` comment.
fn supergrain_args(line: &str) -> Option<Vec<String>> {
    let code = line.split(" #").next().unwrap_or("").trim();
    let rest = if let Some(rest) = code.strip_prefix("supergrain ") {
        rest
    } else if code.starts_with("cargo run ") && code.contains("-p supergrain-cli") {
        code.split_once(" -- ")?.1
    } else {
        return None;
    };
    assert!(
        !rest.contains(['\'', '"', '|', '<', '>', '$', '`']),
        "`{line}`: keep the slow examples' commands plain (no quotes, pipes or redirections) so \
         that they can be checked"
    );
    Some(rest.split_whitespace().map(str::to_string).collect())
}

/// Asks the binary to parse `args` up to a `--help` appended at the end.
fn assert_parses(args: &[String], context: &str) {
    let o = Command::new(env!("CARGO_BIN_EXE_supergrain"))
        .args(args)
        .arg("--help")
        .output()
        .expect("run supergrain");
    assert!(
        o.status.success() && stdout(&o).contains("Usage:"),
        "{context}: `supergrain {}` does not parse:\n{}",
        args.join(" "),
        stderr(&o)
    );
}

/// A temporary folder with a copy of `examples/scenes/`, as the README's examples expect.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let scenes = dir.path().join("examples/scenes");
    std::fs::create_dir_all(&scenes).expect("create examples/scenes");
    for entry in std::fs::read_dir(repo().join("examples/scenes")).expect("examples/scenes") {
        let path = entry.expect("entry").path();
        std::fs::copy(&path, scenes.join(path.file_name().expect("a name"))).expect("copy");
    }
    dir
}

#[test]
fn the_readme_quick_examples_run_verbatim() {
    let readme = read(&repo().join("README.md"));
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_supergrain"));
    let path = std::env::join_paths(
        std::iter::once(bin.parent().expect("the binary's folder").to_path_buf()).chain(
            std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
        ),
    )
    .expect("PATH");
    let dir = workdir();
    let (mut commands, mut transcripts) = (0, 0);
    for block in blocks(&readme).iter().filter(|b| b.lang == "sh") {
        for ex in examples(block) {
            assert!(
                !ex.command.starts_with("cargo "),
                "README line {}: `{}`: cargo commands go in ```bash blocks (not run here)",
                ex.line,
                ex.command
            );
            let o = Command::new("sh")
                .arg("-c")
                .arg(&ex.command)
                .current_dir(dir.path())
                .env("PATH", &path)
                .output()
                .expect("run sh");
            let err = stderr(&o);
            assert!(
                o.status.success() && !err.contains("panicked"),
                "README line {}: `{}` failed ({:?}):\n{err}",
                ex.line,
                ex.command,
                o.status
            );
            if let Some(expected) = &ex.output {
                assert_eq!(
                    stdout(&o),
                    *expected,
                    "README line {}: `{}` answers otherwise than the README shows",
                    ex.line,
                    ex.command
                );
                transcripts += 1;
            }
            commands += 1;
        }
    }
    // The README shows every command at least once in a quick example, and its sample output of
    // `contact` (so that the convention cannot be lost silently).
    assert!(commands >= 15, "only {commands} quick examples found");
    assert!(transcripts >= 1, "no sample output found");
    for name in [
        "circles.png",
        "state.json",
        "later.json",
        "heap.png",
        "state.png",
        "answers.jsonl",
    ] {
        assert!(dir.path().join(name).is_file(), "no {name} written");
    }
}

#[test]
fn the_readme_scene_reference_is_a_valid_scene() {
    let readme = read(&repo().join("README.md"));
    let scene = blocks(&readme)
        .into_iter()
        .find(|b| b.lang == "toml" && b.lines.iter().any(|l| l.starts_with("[box]")))
        .expect("the scene file reference");
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("scene.toml");
    std::fs::write(&file, scene.lines.join("\n")).expect("write scene");
    let o = Command::new(env!("CARGO_BIN_EXE_supergrain"))
        .args(["run", "--steps", "20", "--quiet"])
        .arg(&file)
        .output()
        .expect("run supergrain");
    assert!(
        o.status.success(),
        "README line {}: the scene reference is refused:\n{}",
        scene.line,
        stderr(&o)
    );
}

#[test]
fn every_slow_example_parses() {
    let mut files = vec![repo().join("README.md")];
    for entry in std::fs::read_dir(repo().join("docs")).expect("docs") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    let mut checked = 0;
    for file in &files {
        let text = read(file);
        for block in blocks(&text)
            .iter()
            .filter(|b| b.lang == "bash" || b.lang == "sh")
        {
            for (k, line) in block.lines.iter().enumerate() {
                let line = line.strip_prefix("$ ").unwrap_or(line);
                if let Some(args) = supergrain_args(line) {
                    let context = format!("{} line {}", file.display(), block.line + 1 + k);
                    assert_parses(&args, &context);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 20, "only {checked} commands checked");
}

/// GitHub's anchor of a heading: lower case, spaces to hyphens, other punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(markdown: &str) -> Vec<String> {
    let mut in_code = false;
    let mut out = Vec::new();
    for line in markdown.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
        } else if !in_code && line.starts_with('#') {
            out.push(anchor(line.trim_start_matches('#')));
        }
    }
    out
}

/// The targets of the links and pictures `[..](target)` of a markdown text, outside code, with
/// the line of each.
fn links(markdown: &str) -> Vec<(usize, String)> {
    let mut in_code = false;
    let mut out = Vec::new();
    for (k, line) in markdown.lines().enumerate() {
        if line.starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Code spans hold no links.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(start) = rest.find("](") {
            let after = &rest[start + 2..];
            let end = after.find(')').unwrap_or(after.len());
            out.push((k + 1, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_points_at_something_that_exists() {
    let mut files = vec![repo().join("README.md")];
    for entry in std::fs::read_dir(repo().join("docs")).expect("docs") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    files.push(repo().join("docs/figures/captions.md"));
    let mut checked = 0;
    for file in &files {
        let text = read(file);
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, fragment) = match target.split_once('#') {
                Some((p, f)) => (p, Some(f)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                file.clone()
            } else {
                file.parent().expect("a folder").join(path)
            };
            assert!(
                resolved.exists(),
                "{} line {line}: the link `{target}` points at nothing",
                file.display()
            );
            if let Some(fragment) = fragment {
                assert!(
                    anchors(&read(&resolved)).iter().any(|a| a == fragment),
                    "{} line {line}: `{target}`: no heading `#{fragment}` in {}",
                    file.display(),
                    resolved.display()
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} links checked");
}
