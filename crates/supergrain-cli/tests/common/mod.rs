//! What the end-to-end tests share: running the built binary as a user would, the error
//! contract's checks, and a tiny scene.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The built binary, or `SUPERGRAIN_BIN` when set (another build, an older one say, to see a
/// test fail before its fix).
pub fn supergrain() -> Command {
    match std::env::var_os("SUPERGRAIN_BIN") {
        Some(bin) => Command::new(bin),
        None => Command::new(env!("CARGO_BIN_EXE_supergrain")),
    }
}

/// Runs `supergrain` with `args`, stdin closed, stdout and stderr captured (so neither is a
/// terminal).
pub fn sg(args: &[&str]) -> Output {
    supergrain()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
        .expect("run supergrain")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).expect("stderr is UTF-8")
}

/// Asserts success without a panic; returns stderr.
pub fn ok(o: &Output) -> String {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "the command panicked:\n{err}");
    assert!(
        o.status.success(),
        "expected success, got {:?}\nstdout:\n{}\nstderr:\n{err}",
        o.status,
        stdout(o),
    );
    err
}

/// Asserts a clean failure (exit code 1, an `error:` message, no panic, nothing on stdout);
/// returns stderr.
pub fn failed(o: &Output) -> String {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "the command panicked:\n{err}");
    assert_eq!(
        o.status.code(),
        Some(1),
        "expected exit code 1, got {:?}\nstderr:\n{err}",
        o.status
    );
    assert!(err.starts_with("error: "), "no error message:\n{err}");
    assert!(stdout(o).is_empty(), "stdout not empty: {}", stdout(o));
    err
}

pub fn p(path: &Path) -> &str {
    path.to_str().expect("UTF-8 temp path")
}

/// File names in `dir` (hidden ones included), sorted.
pub fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

pub fn read_bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

/// A tiny circles scene whose grains land and pile up within 150 steps: a 2 x 1 box, six discs
/// of radius 0.2 to 0.3; many contacts, fast.
pub const TINY_CIRCLES: &str = "\
seed = 5
steps = 200

[box]
left = -1.0
right = 1.0
floor = 0.0
top = 1.0

[spawn]
interval = 1

[[group]]
name = \"discs\"
count = 6
radius = [0.2, 0.3]
";

pub fn write_scene(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write scene");
    path
}

/// A legacy VTK point file, parsed.
pub struct Vtk {
    pub points: Vec<[f64; 3]>,
    pub vectors: BTreeMap<String, Vec<[f64; 3]>>,
    pub scalars: BTreeMap<String, Vec<f64>>,
}

pub fn parse_vtk(text: &str) -> Vtk {
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("# vtk DataFile Version"),
        "not a legacy VTK file: {:?}",
        lines[0]
    );
    assert!(lines.contains(&"ASCII"), "not ASCII");
    assert!(lines.contains(&"DATASET POLYDATA"), "not POLYDATA");
    let floats = |line: &str| -> Vec<f64> {
        line.split_whitespace()
            .map(|t| t.parse().unwrap_or_else(|e| panic!("{t:?}: {e}")))
            .collect()
    };
    let triple = |line: &str| -> [f64; 3] {
        let v = floats(line);
        assert_eq!(v.len(), 3, "not three numbers: {line:?}");
        [v[0], v[1], v[2]]
    };
    let mut vtk = Vtk {
        points: Vec::new(),
        vectors: BTreeMap::new(),
        scalars: BTreeMap::new(),
    };
    let mut n = None;
    let mut i = 0;
    while i < lines.len() {
        let words: Vec<&str> = lines[i].split_whitespace().collect();
        match words.as_slice() {
            ["POINTS", count, "double"] => {
                let count: usize = count.parse().expect("POINTS count");
                vtk.points = lines[i + 1..i + 1 + count]
                    .iter()
                    .map(|l| triple(l))
                    .collect();
                n = Some(count);
                i += 1 + count;
            }
            ["POINT_DATA", count] => {
                assert_eq!(Some(count.parse().expect("POINT_DATA count")), n);
                i += 1;
            }
            ["VECTORS", name, "double"] => {
                let count = n.expect("VECTORS before POINTS");
                let v = lines[i + 1..i + 1 + count]
                    .iter()
                    .map(|l| triple(l))
                    .collect();
                vtk.vectors.insert(name.to_string(), v);
                i += 1 + count;
            }
            ["SCALARS", name, "double" | "int", "1"] => {
                let count = n.expect("SCALARS before POINTS");
                assert_eq!(lines[i + 1], "LOOKUP_TABLE default");
                let v = lines[i + 2..i + 2 + count]
                    .iter()
                    .map(|l| {
                        let v = floats(l);
                        assert_eq!(v.len(), 1, "not one number: {l:?}");
                        v[0]
                    })
                    .collect();
                vtk.scalars.insert(name.to_string(), v);
                i += 2 + count;
            }
            _ => i += 1,
        }
    }
    assert!(n.is_some(), "no POINTS section");
    vtk
}
